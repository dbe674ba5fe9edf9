// The publishing side of dds_loopback_test, a separate process with its own
// participant: io_dds_test_publisher DOMAIN_ID TOPIC_PREFIX (e.g. "rt/t123/"). Sends
// kLoopbackMessages of each input type (dds_loopback_messages.h) in time order, then three bad
// messages, and exits once every reader has acknowledged everything.
// Exit codes: 0 sent, 2 usage, 3 no reader matched, 4 DDS failure.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>

#include "dds_loopback_messages.h"
#include "groundline/io/dds_convert_sensors.h"
#include "groundline/io/dds_pubsub.h"

namespace {

using namespace groundline;
using namespace groundline::io;

int Fail(const core::Status& s) {
  std::fprintf(stderr, "io_dds_test_publisher: %s\n", s.message().c_str());
  return 4;
}

int Run(unsigned domain_id, const std::string& prefix) {
  DdsParticipantOptions options;
  options.domain_id = domain_id;
  core::Result<DdsParticipant> participant = DdsParticipant::Create(options);
  if (!participant.ok()) return Fail(participant.status());
  const QosPreset qos = QosPreset::kLossless;
  auto odom = DdsPublisher<RosOdometry>::Create(*participant, prefix + "odom", qos);
  auto joints = DdsPublisher<RosJointState>::Create(*participant, prefix + "joint_states", qos);
  auto scan = DdsPublisher<RosLaserScan>::Create(*participant, prefix + "scan", qos);
  auto image = DdsPublisher<RosImage>::Create(*participant, prefix + "camera/image_raw", qos);
  for (const core::Status* s :
       {&odom.status(), &joints.status(), &scan.status(), &image.status()}) {
    if (!s->ok()) return Fail(*s);
  }
  for (const DdsEntity* w :
       {&odom->writer(), &joints->writer(), &scan->writer(), &image->writer()}) {
    if (!WaitForMatches(*w, true, 1, std::chrono::seconds(60))) {
      std::fprintf(stderr, "io_dds_test_publisher: no reader matched within 60 s\n");
      return 3;
    }
  }
  for (int i = 0; i < testing::kLoopbackMessages; ++i) {
    WheelJointState js;
    js.stamp_s = testing::LoopbackStamp(i);
    js.names = {"caster", "left_wheel_joint", "right_wheel_joint"};
    js.position_rad = {9.0, testing::LoopbackLeftWheel_rad(i), testing::LoopbackRightWheel_rad(i)};
    const core::Status sent[] = {
        odom->Write(ToOdometry(testing::LoopbackOdometry(i)).msg()),
        joints->Write(ToJointState(js).msg()),
        scan->Write(ToLaserScan(testing::LoopbackScan(i), "laser").msg()),
        image->Write(ToMono8Image(testing::LoopbackImage(i), testing::LoopbackStamp(i) + 0.02,
                                  "camera_optical")
                         .msg())};
    for (const core::Status& s : sent) {
      if (!s.ok()) return Fail(s);
    }
  }
  const int last = testing::kLoopbackMessages - 1;
  // Bad 1: a scan whose ranges disagree with its angles.
  DdsSample<RosLaserScan> bad_count = ToLaserScan(testing::LoopbackScan(last), "laser");
  bad_count.msg().header.stamp = ToRosTime(testing::LoopbackStamp(last) + 0.06);
  bad_count.msg().ranges._length -= 1;
  // Bad 2: a scan 50 s older than the stream.
  core::LaserScan stale_scan = testing::LoopbackScan(0);
  stale_scan.stamp_s = testing::LoopbackStamp(0) - 50.0;
  // Bad 3: odometry with a NaN position.
  PlanarOdometry nan_odom = testing::LoopbackOdometry(last);
  nan_odom.stamp_s += 0.05;
  DdsSample<RosOdometry> bad_odom = ToOdometry(nan_odom);
  bad_odom.msg().pose.pose.position.x = std::numeric_limits<double>::quiet_NaN();
  for (const core::Status& s :
       {scan->Write(bad_count.msg()), scan->Write(ToLaserScan(stale_scan, "laser").msg()),
        odom->Write(bad_odom.msg())}) {
    if (!s.ok()) return Fail(s);
  }
  for (const DdsEntity* w :
       {&odom->writer(), &joints->writer(), &scan->writer(), &image->writer()}) {
    const dds_return_t rc = dds_wait_for_acks(w->get(), DDS_SECS(60));
    if (rc != DDS_RETCODE_OK) return Fail(core::Status::Error(DdsErrorText("wait for acks", rc)));
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: io_dds_test_publisher DOMAIN_ID TOPIC_PREFIX\n");
    return 2;
  }
  return Run(static_cast<unsigned>(std::strtoul(argv[1], nullptr, 10)), argv[2]);
}
