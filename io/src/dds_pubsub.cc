#include "groundline/io/dds_pubsub.h"

#include <thread>

namespace groundline::io {

core::Result<std::uint32_t> MatchedReaders(const DdsEntity& writer) {
  dds_publication_matched_status_t status;
  const dds_return_t rc = dds_get_publication_matched_status(writer.get(), &status);
  if (rc != DDS_RETCODE_OK) return core::Status::Error(DdsErrorText("publication matched", rc));
  return status.current_count;
}

core::Result<std::uint32_t> MatchedWriters(const DdsEntity& reader) {
  dds_subscription_matched_status_t status;
  const dds_return_t rc = dds_get_subscription_matched_status(reader.get(), &status);
  if (rc != DDS_RETCODE_OK) return core::Status::Error(DdsErrorText("subscription matched", rc));
  return status.current_count;
}

bool WaitForMatches(const DdsEntity& endpoint, bool endpoint_is_writer, std::uint32_t n,
                    std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    const core::Result<std::uint32_t> count =
        endpoint_is_writer ? MatchedReaders(endpoint) : MatchedWriters(endpoint);
    if (count.ok() && *count >= n) return true;
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

core::Result<DdsWaitSet> DdsWaitSet::Create(const DdsParticipant& participant) {
  const dds_entity_t ws = dds_create_waitset(participant.get());
  if (ws < 0) return core::Status::Error(DdsErrorText("DDS waitset", ws));
  return DdsWaitSet(DdsEntity(ws));
}

core::Status DdsWaitSet::Attach(const DdsEntity& reader) {
  const dds_entity_t cond = dds_create_readcondition(reader.get(), DDS_ANY_STATE);
  if (cond < 0) return core::Status::Error(DdsErrorText("DDS read condition", cond));
  DdsEntity owned(cond);
  const dds_return_t rc = dds_waitset_attach(waitset_.get(), cond, 0);
  if (rc != DDS_RETCODE_OK) return core::Status::Error(DdsErrorText("DDS waitset attach", rc));
  conditions_.push_back(std::move(owned));
  return core::Status::Ok();
}

core::Result<bool> DdsWaitSet::Wait(std::chrono::milliseconds timeout) const {
  const dds_return_t rc = dds_waitset_wait(waitset_.get(), nullptr, 0, DDS_MSECS(timeout.count()));
  if (rc < 0) return core::Status::Error(DdsErrorText("DDS waitset wait", rc));
  return rc > 0;
}

}  // namespace groundline::io
