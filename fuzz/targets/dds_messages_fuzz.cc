// The ROS 2 messages the service takes over DDS (io/dds_inputs.h): bytes as
// they arrive on the wire, deserialized the way CycloneDDS's default serdata
// does it on receipt (dds_stream_normalize_data checks the CDR against the
// type's descriptor, then dds_stream_read fills the C struct), then checked
// and converted by the same functions as DdsInputs.
//
// Input: byte 0 picks the type (bits 0-2: odometry, joint state, laser scan,
// image, initial pose) and whether frame ids are checked (bit 3); the rest is
// the serialized sample with its 4-byte encapsulation header (CDR_BE 00 00,
// CDR_LE 00 01, as rmw_cyclonedds writes plain CDR).
//
// Contracts: a message the validator accepts converts without error to
// finite values (a scan has one range per ray, an image is width x height).
#include <dds/dds.h>
#include <dds/ddsi/ddsi_cdrstream.h>
#include <dds/ddsrt/endian.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "fuzz_input.h"
#include "groundline/io/dds_convert.h"
#include "groundline/io/dds_convert_sensors.h"
#include "groundline/io/dds_types.h"
#include "groundline/io/dds_validate.h"

namespace gio = groundline::io;
namespace gf = groundline::fuzz;

namespace {

// Plain CDR (CDR_ENC_VERSION_1 of dds/ddsi/q_protocol.h).
constexpr std::uint32_t kXcdr1 = 1;

// Deserializes `payload` (after the encapsulation header) into a zeroed T.
// False where CycloneDDS would drop the sample as malformed.
template <typename T>
bool Deserialize(const std::uint8_t* data, std::size_t size, gio::DdsSample<T>* sample) {
  if (size < 4 || size > 0x7fffffff) return false;
  const bool little = data[0] == 0x00 && data[1] == 0x01;
  const bool big = data[0] == 0x00 && data[1] == 0x00;
  if (!little && !big) return false;  // only plain CDR (XCDR1) is ROS 2's
  // The stream is normalized in place: an 8-byte aligned copy.
  std::vector<std::uint64_t> buffer((size - 4 + 7) / 8 + 1);
  std::memcpy(buffer.data(), data + 4, size - 4);
  const auto payload_size = static_cast<std::uint32_t>(size - 4);
  const bool host_little = DDSRT_ENDIAN == DDSRT_LITTLE_ENDIAN;
  const bool bswap = little != host_little;
  const dds_topic_descriptor_t& desc = gio::DdsTraits<T>::descriptor();
  std::uint32_t offset = 0;
  if (dds_stream_normalize_data(reinterpret_cast<char*>(buffer.data()), &offset, payload_size,
                                bswap, kXcdr1, desc.m_ops) == nullptr) {
    return false;
  }
  dds_istream_t is;
  dds_istream_init(&is, payload_size, buffer.data(), kXcdr1);
  dds_stream_read(&is, reinterpret_cast<char*>(&sample->msg()), desc.m_ops);
  return true;
}

// Whether the validator accepted the message; a refusal must say why.
bool Accepted(const groundline::core::Status& valid) {
  if (!valid.ok()) gf::FuzzCheck(!valid.message().empty(), "an error has a message");
  return valid.ok();
}

gio::DdsCheck Check(bool frames, const char* frame) {
  gio::DdsCheck check;
  if (frames) check.frame_id = frame;
  return check;
}

void Odometry(const std::uint8_t* data, std::size_t size, bool frames) {
  gio::DdsSample<gio::RosOdometry> s;
  if (!Deserialize(data, size, &s)) return;
  const auto valid = gio::ValidateOdometry(s.msg(), Check(frames, "odom"), frames ? "base_link" : "");
  if (!Accepted(valid)) return;
  const gio::PlanarOdometry o = gio::FromOdometry(s.msg());
  gf::FuzzCheck(std::isfinite(o.stamp_s) && std::isfinite(o.T_odom_base.x()) &&
                    std::isfinite(o.T_odom_base.y()) && std::isfinite(o.T_odom_base.yaw()),
                "an accepted odometry converts to a finite pose");
}

void JointState(const std::uint8_t* data, std::size_t size, bool frames) {
  gio::DdsSample<gio::RosJointState> s;
  if (!Deserialize(data, size, &s)) return;
  const auto valid = gio::ValidateJointState(s.msg(), Check(frames, "base_link"),
                                             {"left_wheel_joint", "right_wheel_joint"});
  Accepted(valid);
}

void Scan(const std::uint8_t* data, std::size_t size, bool frames) {
  gio::DdsSample<gio::RosLaserScan> s;
  if (!Deserialize(data, size, &s)) return;
  const auto valid = gio::ValidateLaserScan(s.msg(), Check(frames, "laser"));
  if (!Accepted(valid)) return;
  const groundline::core::LaserScan scan = gio::FromLaserScan(s.msg());
  gf::FuzzCheck(scan.ranges_m.size() == s.msg().ranges._length,
                "an accepted scan keeps one range per ray");
}

void Image(const std::uint8_t* data, std::size_t size, bool frames) {
  gio::DdsSample<gio::RosImage> s;
  if (!Deserialize(data, size, &s)) return;
  const auto valid = gio::ValidateImage(s.msg(), Check(frames, "camera"));
  if (!Accepted(valid)) return;
  const auto grey = gio::FromMono8Image(s.msg());
  gf::FuzzCheck(grey.ok() && grey->cols == static_cast<int>(s.msg().width) &&
                    grey->rows == static_cast<int>(s.msg().height),
                "an accepted image converts to width x height pixels");
}

void InitialPose(const std::uint8_t* data, std::size_t size, bool frames) {
  gio::DdsSample<gio::RosPoseWithCovarianceStamped> s;
  if (!Deserialize(data, size, &s)) return;
  const auto valid = gio::ValidatePoseWithCovarianceStamped(s.msg(), Check(frames, "map"));
  if (!Accepted(valid)) return;
  const gio::PlanarPoseStamped p = gio::FromPoseWithCovarianceStamped(s.msg());
  gf::FuzzCheck(std::isfinite(p.T_frame_base.x()) && std::isfinite(p.T_frame_base.yaw()) &&
                    p.covariance.allFinite(),
                "an accepted initial pose converts to finite values");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const bool frames = (data[0] & 0x08) != 0;
  switch (data[0] & 0x07) {
    case 0: Odometry(data + 1, size - 1, frames); break;
    case 1: JointState(data + 1, size - 1, frames); break;
    case 2: Scan(data + 1, size - 1, frames); break;
    case 3: Image(data + 1, size - 1, frames); break;
    case 4: InitialPose(data + 1, size - 1, frames); break;
    default: break;
  }
  return 0;
}
