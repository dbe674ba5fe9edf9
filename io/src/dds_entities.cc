#include "groundline/io/dds_entities.h"

#include <charconv>
#include <cstdlib>
#include <string_view>

#include "dds_loopback_config.h"

namespace groundline::io {

DdsEntity& DdsEntity::operator=(DdsEntity&& other) noexcept {
  if (this != &other) {
    Reset();
    handle_ = other.Release();
  }
  return *this;
}

void DdsEntity::Reset() {
  // A handle already deleted with its parent returns BAD_PARAMETER: harmless.
  if (handle_ > 0) dds_delete(handle_);
  handle_ = 0;
}

std::string DdsErrorText(const std::string& what, dds_return_t rc) {
  return what + ": " + dds_strretcode(rc);
}

core::Result<std::uint32_t> DomainIdFromEnvironment() {
  const char* text = std::getenv("ROS_DOMAIN_ID");
  if (text == nullptr || *text == '\0') return std::uint32_t{0};
  const std::string_view s(text);
  std::uint32_t id = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), id);
  if (ec != std::errc() || end != s.data() + s.size() || id > kMaxRosDomainId) {
    return core::Status::Error("ROS_DOMAIN_ID: expected an integer in [0, " +
                               std::to_string(kMaxRosDomainId) + "], got '" + std::string(s) + "'");
  }
  return id;
}

core::Status DdsParticipantOptions::Validate() const {
  if (domain_id && *domain_id > kMaxRosDomainId) {
    return core::Status::Error(
        "DdsParticipantOptions.domain_id: expected <= " + std::to_string(kMaxRosDomainId) +
        ", got " + std::to_string(*domain_id));
  }
  return core::Status::Ok();
}

const std::string& LoopbackConfigXml() {
  static const std::string kXml(kLoopbackConfigXmlText);
  return kXml;
}

core::Result<DdsParticipant> DdsParticipant::Create(const DdsParticipantOptions& options) {
  if (core::Status s = options.Validate(); !s.ok()) return s;
  std::uint32_t domain_id = 0;
  if (options.domain_id) {
    domain_id = *options.domain_id;
  } else {
    core::Result<std::uint32_t> env = DomainIdFromEnvironment();
    if (!env.ok()) return env.status();
    domain_id = *env;
  }

  DdsParticipant p;
  p.domain_id_ = domain_id;
  const char* uri = std::getenv("CYCLONEDDS_URI");
  std::string config;
  if (!options.config.empty()) {
    config = options.config;
    p.config_source_ = "options";
  } else if (uri != nullptr && *uri != '\0') {
    p.config_source_ = "CYCLONEDDS_URI";
  } else {
    config = LoopbackConfigXml();
    p.config_source_ = "loopback";
  }
  if (!config.empty()) {
    const dds_entity_t domain = dds_create_domain(domain_id, config.c_str());
    if (domain > 0) {
      p.domain_ = DdsEntity(domain);
    } else if (domain != DDS_RETCODE_PRECONDITION_NOT_MET) {
      // PRECONDITION_NOT_MET: the domain exists in this process already and
      // keeps the configuration it was created with.
      return core::Status::Error(DdsErrorText("DDS domain " + std::to_string(domain_id) +
                                                  " with the " + p.config_source_ +
                                                  " configuration (check the XML)",
                                              domain));
    }
  }
  const dds_entity_t participant = dds_create_participant(domain_id, nullptr, nullptr);
  if (participant < 0) {
    return core::Status::Error(DdsErrorText("DDS participant on domain " +
                                                std::to_string(domain_id) + " (" +
                                                p.config_source_ + " configuration)",
                                            participant));
  }
  p.participant_ = DdsEntity(participant);
  return p;
}

core::Result<DdsEntity> CreateTopic(const DdsParticipant& participant,
                                    const dds_topic_descriptor_t& descriptor,
                                    const std::string& name) {
  const dds_entity_t topic =
      dds_create_topic(participant.get(), &descriptor, name.c_str(), nullptr, nullptr);
  if (topic < 0) {
    return core::Status::Error(
        DdsErrorText("DDS topic '" + name + "' of type " + descriptor.m_typename, topic));
  }
  return DdsEntity(topic);
}

core::Result<DdsEntity> CreateReader(const DdsParticipant& participant, const DdsEntity& topic,
                                     QosPreset qos) {
  const DdsQos q = MakeQos(qos);
  const dds_entity_t reader = dds_create_reader(participant.get(), topic.get(), q.get(), nullptr);
  if (reader < 0) {
    return core::Status::Error(
        DdsErrorText(std::string("DDS reader (QoS ") + QosPresetName(qos) + ")", reader));
  }
  return DdsEntity(reader);
}

core::Result<DdsEntity> CreateWriter(const DdsParticipant& participant, const DdsEntity& topic,
                                     QosPreset qos) {
  const DdsQos q = MakeQos(qos);
  const dds_entity_t writer = dds_create_writer(participant.get(), topic.get(), q.get(), nullptr);
  if (writer < 0) {
    return core::Status::Error(
        DdsErrorText(std::string("DDS writer (QoS ") + QosPresetName(qos) + ")", writer));
  }
  return DdsEntity(writer);
}

}  // namespace groundline::io
