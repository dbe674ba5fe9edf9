// Typed writer and reader of one ROS 2 topic: DdsPublisher<T> and
// DdsSubscriber<T>, T one of the wire types of dds_types.h. Each owns its
// topic, its writer/reader and (subscriber) a waitset, all children of the
// participant, which must outlive them.
//
// Thread-safety: Write and Take may be called from different threads
// (CycloneDDS locks internally); one object is not meant to be shared.
#ifndef GROUNDLINE_IO_DDS_PUBSUB_H_
#define GROUNDLINE_IO_DDS_PUBSUB_H_

#include <chrono>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "groundline/core/status.h"
#include "groundline/io/dds_entities.h"
#include "groundline/io/dds_qos.h"
#include "groundline/io/dds_types.h"

namespace groundline::io {

// How many matched remote or local endpoints a writer (reader) has.
core::Result<std::uint32_t> MatchedReaders(const DdsEntity& writer);
core::Result<std::uint32_t> MatchedWriters(const DdsEntity& reader);

// Polls `count_fn` every 10 ms until it returns >= n or `timeout` passes;
// false on timeout. For tools that should not publish into the void.
bool WaitForMatches(const DdsEntity& endpoint, bool endpoint_is_writer, std::uint32_t n,
                    std::chrono::milliseconds timeout);

template <typename T>
class DdsPublisher {
 public:
  static core::Result<DdsPublisher> Create(const DdsParticipant& participant,
                                           const std::string& topic_name, QosPreset qos) {
    core::Result<DdsEntity> topic =
        CreateTopic(participant, DdsTraits<T>::descriptor(), topic_name);
    if (!topic.ok()) return topic.status();
    core::Result<DdsEntity> writer = CreateWriter(participant, *topic, qos);
    if (!writer.ok()) return writer.status().WithContext(topic_name);
    return DdsPublisher(std::move(*topic), std::move(*writer), topic_name);
  }

  core::Status Write(const T& msg) const {
    const dds_return_t rc = dds_write(writer_.get(), &msg);
    if (rc != DDS_RETCODE_OK) {
      return core::Status::Error(
          DdsErrorText("write " + std::string(DdsTraits<T>::kRosName) + " on " + name_, rc));
    }
    return core::Status::Ok();
  }

  const DdsEntity& writer() const { return writer_; }
  const std::string& topic_name() const { return name_; }

 private:
  DdsPublisher(DdsEntity topic, DdsEntity writer, std::string name)
      : topic_(std::move(topic)), writer_(std::move(writer)), name_(std::move(name)) {}
  // Writer declared after its topic: destroyed first.
  DdsEntity topic_;
  DdsEntity writer_;
  std::string name_;
};

template <typename T>
class DdsSubscriber {
 public:
  static constexpr std::uint32_t kTakeBatch = 16;

  static core::Result<DdsSubscriber> Create(const DdsParticipant& participant,
                                            const std::string& topic_name, QosPreset qos) {
    core::Result<DdsEntity> topic =
        CreateTopic(participant, DdsTraits<T>::descriptor(), topic_name);
    if (!topic.ok()) return topic.status();
    core::Result<DdsEntity> reader = CreateReader(participant, *topic, qos);
    if (!reader.ok()) return reader.status().WithContext(topic_name);
    return DdsSubscriber(std::move(*topic), std::move(*reader), topic_name);
  }

  // Takes every sample available and calls fn(const T&) for each valid one
  // (disposals and unregistrations carry no data and are skipped), in
  // reception order. Samples are loaned: fn must copy what it keeps. Returns
  // the number of samples passed to fn.
  template <typename Fn>
  core::Result<int> Take(Fn&& fn) const {
    int delivered = 0;
    for (;;) {
      void* samples[kTakeBatch] = {};
      dds_sample_info_t infos[kTakeBatch];
      const dds_return_t n = dds_take(reader_.get(), samples, infos, kTakeBatch, kTakeBatch);
      if (n < 0) {
        return core::Status::Error(
            DdsErrorText("take " + std::string(DdsTraits<T>::kRosName) + " on " + name_, n));
      }
      if (n == 0) return delivered;
      // Returned even if fn throws.
      struct LoanGuard {
        dds_entity_t reader;
        void** samples;
        dds_return_t n;
        ~LoanGuard() { dds_return_loan(reader, samples, n); }
      } guard{reader_.get(), samples, n};
      for (dds_return_t i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        fn(*static_cast<const T*>(samples[i]));
        ++delivered;
      }
      if (static_cast<std::uint32_t>(n) < kTakeBatch) return delivered;
    }
  }

  const DdsEntity& reader() const { return reader_; }
  const std::string& topic_name() const { return name_; }

 private:
  DdsSubscriber(DdsEntity topic, DdsEntity reader, std::string name)
      : topic_(std::move(topic)), reader_(std::move(reader)), name_(std::move(name)) {}
  DdsEntity topic_;
  DdsEntity reader_;
  std::string name_;
};

// Waits for data on any of several readers: a waitset over one read
// condition per reader (triggered while the reader holds samples, so nothing
// is missed between a wakeup and the take). Declare it after the subscribers
// it watches so that it is destroyed first.
class DdsWaitSet {
 public:
  static core::Result<DdsWaitSet> Create(const DdsParticipant& participant);

  core::Status Attach(const DdsEntity& reader);
  // True when some attached reader holds data, false when `timeout` passed.
  core::Result<bool> Wait(std::chrono::milliseconds timeout) const;

 private:
  explicit DdsWaitSet(DdsEntity waitset) : waitset_(std::move(waitset)) {}
  DdsEntity waitset_;
  std::vector<DdsEntity> conditions_;
};

}  // namespace groundline::io

#endif  // GROUNDLINE_IO_DDS_PUBSUB_H_
