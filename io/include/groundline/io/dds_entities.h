// RAII over the CycloneDDS 0.10 C API: one owner per dds_entity_t, a
// participant that keeps traffic on the loopback interface unless told
// otherwise, and topic/reader/writer creation with a QoS preset.
//
// Network policy: when CYCLONEDDS_URI is unset and no config is given, the
// participant's domain is created with the loopback configuration compiled
// in from samples/cyclonedds_loopback.xml (127.0.0.1 only, no multicast,
// unicast peer 127.0.0.1), so nothing leaves the machine by default. A
// CYCLONEDDS_URI set by the user is honoured as is.
//
// Thread-safety: the CycloneDDS calls are thread-safe; the wrappers hold no
// other state. Deleting an entity deletes its children (CycloneDDS rule), so
// destroy readers/writers before their participant, as members declared after
// it are.
#ifndef GROUNDLINE_IO_DDS_ENTITIES_H_
#define GROUNDLINE_IO_DDS_ENTITIES_H_

#include <cstdint>
#include <optional>
#include <string>

#include <dds/dds.h>

#include "groundline/core/status.h"
#include "groundline/io/dds_qos.h"

namespace groundline::io {

// Owns one entity handle and dds_delete()s it. Move-only; a default or
// moved-from object holds no entity (handle 0).
class DdsEntity {
 public:
  DdsEntity() = default;
  explicit DdsEntity(dds_entity_t handle) : handle_(handle) {}
  DdsEntity(DdsEntity&& other) noexcept : handle_(other.Release()) {}
  DdsEntity& operator=(DdsEntity&& other) noexcept;
  DdsEntity(const DdsEntity&) = delete;
  DdsEntity& operator=(const DdsEntity&) = delete;
  ~DdsEntity() { Reset(); }

  dds_entity_t get() const { return handle_; }
  explicit operator bool() const { return handle_ > 0; }
  dds_entity_t Release() {
    const dds_entity_t h = handle_;
    handle_ = 0;
    return h;
  }
  void Reset();

 private:
  dds_entity_t handle_ = 0;
};

// "what: dds_strretcode(rc)", for statuses of failed calls.
std::string DdsErrorText(const std::string& what, dds_return_t rc);

// The largest domain id ROS 2 accepts on Linux (port numbers stay < 65536).
inline constexpr std::uint32_t kMaxRosDomainId = 232;

// ROS_DOMAIN_ID as ROS 2 reads it: unset or empty -> 0; otherwise a decimal
// integer in [0, kMaxRosDomainId], or an error naming the variable and value.
core::Result<std::uint32_t> DomainIdFromEnvironment();

struct DdsParticipantOptions {
  // Unset: DomainIdFromEnvironment().
  std::optional<std::uint32_t> domain_id;
  // A CycloneDDS configuration (XML text or file://URI). Empty: CYCLONEDDS_URI
  // when set, else the compiled-in loopback configuration.
  std::string config;

  core::Status Validate() const;
};

// The compiled-in loopback configuration (samples/cyclonedds_loopback.xml).
const std::string& LoopbackConfigXml();

class DdsParticipant {
 public:
  // Creates the participant (and, with an explicit or the loopback config,
  // its domain). Within one process, a domain id is configured once: a second
  // participant on the same id shares the first one's configuration and must
  // not outlive the first, whose destruction deletes the domain (one
  // participant per process and domain, as in ROS 2, avoids the question).
  static core::Result<DdsParticipant> Create(const DdsParticipantOptions& options = {});

  dds_entity_t get() const { return participant_.get(); }
  std::uint32_t domain_id() const { return domain_id_; }
  // Where the configuration came from: "CYCLONEDDS_URI", "options" or "loopback".
  const std::string& config_source() const { return config_source_; }

 private:
  DdsParticipant() = default;
  // Declared first, destroyed last: deleting the domain deletes its participants.
  DdsEntity domain_;
  DdsEntity participant_;
  std::uint32_t domain_id_ = 0;
  std::string config_source_;
};

// A topic of `descriptor` named `name` (with the "rt/" prefix for ROS 2).
core::Result<DdsEntity> CreateTopic(const DdsParticipant& participant,
                                    const dds_topic_descriptor_t& descriptor,
                                    const std::string& name);
core::Result<DdsEntity> CreateReader(const DdsParticipant& participant, const DdsEntity& topic,
                                     QosPreset qos);
core::Result<DdsEntity> CreateWriter(const DdsParticipant& participant, const DdsEntity& topic,
                                     QosPreset qos);

}  // namespace groundline::io

#endif  // GROUNDLINE_IO_DDS_ENTITIES_H_
