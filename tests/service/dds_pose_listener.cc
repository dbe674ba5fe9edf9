// service_dds_pose_listener: the ROS 2 side of the service's DDS outputs, for
// the end-to-end test and scripts/dds_demo.sh. Subscribes to
// <prefix>groundline/pose and <prefix>tf (map -> odom), both reliable
// keep-all so that a busy listener still counts every message (a ROS 2 node
// would read the pose transient local, depth 1: the latest). Writes the
// poses as TUM and prints how many arrived and how late: receive wall time
// minus the pose's stamp, and for map -> odom minus its stamp less the
// transform tolerance (the odometry reading it was computed at). The
// latencies mean something only for wall-clock stamps. Prints
// "listener: matched" once both topics have a publisher. Ends on
// SIGINT/SIGTERM, after --idle seconds without a message once one came, or
// after --timeout seconds.
//   service_dds_pose_listener --out FILE.tum [--prefix rt/] [--stamp-offset S]
//       [--tf-tolerance S] [--idle S] [--timeout S]
// --stamp-offset is subtracted from the stamps written to the TUM file
// (replay-dds --stamps wall prints it), so that they match the dataset's.
// Last line: "poses N tf M pose_latency_ms median P50 p99 P99 tf_latency_ms
// median P50 p99 P99". Exit codes: 0 at least one pose, 1 none or a DDS
// failure, 2 usage.
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "groundline/core/run_timing.h"
#include "groundline/core/trajectory_io.h"
#include "groundline/io/dds_convert.h"
#include "groundline/io/dds_pubsub.h"

namespace {

using namespace groundline;

std::atomic<bool> g_stop{false};
extern "C" void OnStop(int) { g_stop.store(true); }

double WallNowS() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

int Run(const std::string& out_path, const std::string& prefix, double offset_s, double tolerance_s,
        double idle_s, double timeout_s) {
  core::Result<io::DdsParticipant> participant = io::DdsParticipant::Create();
  if (!participant.ok()) {
    std::fprintf(stderr, "listener: %s\n", participant.message().c_str());
    return 1;
  }
  auto pose = io::DdsSubscriber<io::RosPoseWithCovarianceStamped>::Create(
      *participant, prefix + "groundline/pose", io::QosPreset::kLossless);
  auto tf = io::DdsSubscriber<io::RosTfMessage>::Create(*participant, prefix + "tf",
                                                        io::QosPreset::kLossless);
  if (!pose.ok() || !tf.ok()) {
    std::fprintf(stderr, "listener: %s\n", (pose.ok() ? tf.message() : pose.message()).c_str());
    return 1;
  }
  core::Result<io::DdsWaitSet> waitset = io::DdsWaitSet::Create(*participant);
  if (!waitset.ok() || !waitset->Attach(pose->reader()).ok() ||
      !waitset->Attach(tf->reader()).ok()) {
    std::fprintf(stderr, "listener: cannot wait on the readers\n");
    return 1;
  }
  std::ofstream out(out_path);
  if (!out) {
    std::fprintf(stderr, "listener: cannot write %s\n", out_path.c_str());
    return 1;
  }
  std::printf("listener: %sgroundline/pose and %stf on domain %u\n", prefix.c_str(), prefix.c_str(),
              participant->domain_id());
  std::fflush(stdout);
  std::vector<double> pose_latency_ms, tf_latency_ms;
  long poses = 0, transforms = 0;
  const auto start = std::chrono::steady_clock::now();
  auto last_message = start;
  bool matched = false;
  const auto take = [&]() -> core::Result<int> {
    int n = 0;
    const core::Result<int> took_pose = pose->Take([&](const io::RosPoseWithCovarianceStamped& m) {
      const double now_s = WallNowS();
      const io::PlanarPoseStamped p = io::FromPoseWithCovarianceStamped(m);
      pose_latency_ms.push_back(1e3 * (now_s - p.stamp_s));
      out << core::FormatTumLine({p.stamp_s - offset_s, p.T_frame_base, std::nullopt});
      ++poses;
      ++n;
    });
    const core::Result<int> took_tf = tf->Take([&](const io::RosTfMessage& m) {
      const double now_s = WallNowS();
      for (std::uint32_t i = 0; i < m.transforms._length; ++i) {
        const double stamp_s = io::FromRosTime(m.transforms._buffer[i].header.stamp);
        tf_latency_ms.push_back(1e3 * (now_s - (stamp_s - tolerance_s)));
        ++transforms;
      }
      ++n;
    });
    if (!took_pose.ok()) return took_pose.status();
    if (!took_tf.ok()) return took_tf.status();
    return n;
  };
  while (!g_stop.load()) {
    if (!waitset->Wait(std::chrono::milliseconds(100)).ok()) return 1;
    if (!matched) {
      const core::Result<std::uint32_t> a = io::MatchedWriters(pose->reader());
      const core::Result<std::uint32_t> b = io::MatchedWriters(tf->reader());
      if (a.ok() && b.ok() && *a > 0 && *b > 0) {
        matched = true;
        std::printf("listener: matched\n");
        std::fflush(stdout);
      }
    }
    const core::Result<int> n = take();
    if (!n.ok()) {
      std::fprintf(stderr, "listener: %s\n", n.message().c_str());
      return 1;
    }
    const auto now = std::chrono::steady_clock::now();
    if (*n > 0) last_message = now;
    if (poses + transforms > 0 &&
        std::chrono::duration<double>(now - last_message).count() > idle_s)
      break;
    if (std::chrono::duration<double>(now - start).count() > timeout_s) break;
  }
  // What arrived between the last wait and the stop.
  if (!take().ok()) return 1;
  out.flush();
  std::printf(
      "poses %ld tf %ld pose_latency_ms median %.2f p99 %.2f tf_latency_ms median %.2f p99 %.2f\n",
      poses, transforms, core::Percentile(pose_latency_ms, 0.5),
      core::Percentile(pose_latency_ms, 0.99), core::Percentile(tf_latency_ms, 0.5),
      core::Percentile(tf_latency_ms, 0.99));
  return poses > 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  std::string out_path, prefix = "rt/";
  double offset_s = 0.0, tolerance_s = 0.1, idle_s = 1e9, timeout_s = 3600.0;
  for (int i = 1; i < argc; ++i) {
    const auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
    const char* flag = argv[i];
    const char* v = value();
    if (v == nullptr) {
      std::fprintf(stderr, "listener: %s needs a value\n", flag);
      return 2;
    }
    if (std::strcmp(flag, "--out") == 0) {
      out_path = v;
    } else if (std::strcmp(flag, "--prefix") == 0) {
      prefix = v;
    } else if (std::strcmp(flag, "--stamp-offset") == 0) {
      offset_s = std::atof(v);
    } else if (std::strcmp(flag, "--tf-tolerance") == 0) {
      tolerance_s = std::atof(v);
    } else if (std::strcmp(flag, "--idle") == 0) {
      idle_s = std::atof(v);
    } else if (std::strcmp(flag, "--timeout") == 0) {
      timeout_s = std::atof(v);
    } else {
      std::fprintf(stderr,
                   "usage: service_dds_pose_listener --out FILE.tum [--prefix rt/] "
                   "[--stamp-offset S] [--tf-tolerance S] [--idle S] [--timeout S]\n");
      return 2;
    }
  }
  if (out_path.empty()) {
    std::fprintf(stderr, "listener: --out FILE.tum is required\n");
    return 2;
  }
  std::signal(SIGINT, OnStop);
  std::signal(SIGTERM, OnStop);
  return Run(out_path, prefix, offset_s, tolerance_s, idle_s, timeout_s);
}
