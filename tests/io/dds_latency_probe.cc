// io_dds_latency_probe: publish -> receive latency of groundline's DDS layer
// between two processes on the loopback configuration. Not a test (timing is
// never asserted); a measurement for docs/dds.md.
//   io_dds_latency_probe odometry|scan|image [COUNT] [PERIOD_MS]
// The parent spawns itself as the receiver, waits for the match, then
// publishes COUNT messages (default 1000) every PERIOD_MS (default 10 ms),
// each stamped with CLOCK_MONOTONIC (shared by the processes of one
// machine). The receiver reports the median, 90th percentile and maximum of
// receive time minus stamp: serialization, the loopback UDP path,
// deserialization and the take, i.e. what the service's Poll would see.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include <opencv2/core.hpp>

#include "groundline/io/dds_convert.h"
#include "groundline/io/dds_convert_sensors.h"
#include "groundline/io/dds_pubsub.h"

extern char** environ;

namespace {

using namespace groundline;
using namespace groundline::io;

constexpr unsigned kDomainId = 176;

double MonotonicNow_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

core::LaserScan ProbeScan() {  // the simulated LiDAR: 270 deg at 0.33 deg
  core::LaserScan s;
  s.angle_min_rad = -2.356;
  s.angle_increment_rad = 0.00576;
  s.range_min_m = 0.05;
  s.range_max_m = 25.0;
  s.ranges_m.assign(819, 5.0);
  return s;
}

template <typename T>
int Receive(const std::string& topic, int count) {
  core::Result<DdsParticipant> p = DdsParticipant::Create({kDomainId, ""});
  if (!p.ok()) return 1;
  auto sub = DdsSubscriber<T>::Create(*p, topic, QosPreset::kLossless);
  auto ws = DdsWaitSet::Create(*p);
  if (!sub.ok() || !ws.ok() || !ws->Attach(sub->reader()).ok()) return 1;
  std::vector<double> latency_us;
  while (static_cast<int>(latency_us.size()) < count) {
    core::Result<bool> ready = ws->Wait(std::chrono::seconds(30));
    if (!ready.ok() || !*ready) break;
    const core::Result<int> taken = sub->Take([&](const T& m) {
      latency_us.push_back(1e6 * (MonotonicNow_s() - FromRosTime(m.header.stamp)));
    });
    if (!taken.ok()) break;
  }
  if (latency_us.empty()) return 1;
  std::sort(latency_us.begin(), latency_us.end());
  std::printf("%s: %zu received, latency median %.0f us, p90 %.0f us, max %.0f us\n", topic.c_str(),
              latency_us.size(), latency_us[latency_us.size() / 2],
              latency_us[latency_us.size() * 9 / 10], latency_us.back());
  return static_cast<int>(latency_us.size()) == count ? 0 : 1;
}

template <typename T, typename Make>
int Send(const std::string& topic, int count, int period_ms, Make make) {
  core::Result<DdsParticipant> p = DdsParticipant::Create({kDomainId, ""});
  if (!p.ok()) return 1;
  auto pub = DdsPublisher<T>::Create(*p, topic, QosPreset::kLossless);
  if (!pub.ok() || !WaitForMatches(pub->writer(), true, 1, std::chrono::seconds(30))) return 1;
  for (int i = 0; i < count; ++i) {
    DdsSample<T> msg = make();
    msg.msg().header.stamp = ToRosTime(MonotonicNow_s());  // last: conversion time excluded
    if (!pub->Write(msg.msg()).ok()) return 1;
    std::this_thread::sleep_for(std::chrono::milliseconds(period_ms));
  }
  dds_wait_for_acks(pub->writer().get(), DDS_SECS(30));
  return 0;
}

template <typename T, typename Make>
int Run(bool receiver, const std::string& topic, int count, int period_ms, Make make) {
  return receiver ? Receive<T>(topic, count) : Send<T>(topic, count, period_ms, make);
}

}  // namespace

int main(int argc, char** argv) {
  bool receiver = argc > 1 && std::strcmp(argv[1], "--receive") == 0;
  const int a = receiver ? 2 : 1;
  if (argc <= a) {
    std::fprintf(stderr, "usage: io_dds_latency_probe odometry|scan|image [COUNT] [PERIOD_MS]\n");
    return 2;
  }
  const std::string kind = argv[a];
  const int count = argc > a + 1 ? std::atoi(argv[a + 1]) : 1000;
  const int period_ms = argc > a + 2 ? std::atoi(argv[a + 2]) : 10;
  if (!receiver) {
    if (std::getenv("CYCLONEDDS_URI") == nullptr) {
      std::fprintf(stderr, "(CYCLONEDDS_URI unset: the compiled-in loopback configuration)\n");
    }
    std::vector<std::string> args = {argv[0], "--receive"};
    for (int i = 1; i < argc; ++i) args.push_back(argv[i]);
    std::vector<char*> cargs;
    for (std::string& s : args) cargs.push_back(s.data());
    cargs.push_back(nullptr);
    pid_t pid = -1;
    if (posix_spawn(&pid, argv[0], nullptr, nullptr, cargs.data(), environ) != 0) return 1;
    int rc = 1;
    if (kind == "odometry") {
      rc =
          Run<RosOdometry>(false, "rt/probe/odom", count, period_ms, [] { return ToOdometry({}); });
    } else if (kind == "scan") {
      const core::LaserScan scan = ProbeScan();
      rc = Run<RosLaserScan>(false, "rt/probe/scan", count, period_ms,
                             [&] { return ToLaserScan(scan, "laser"); });
    } else if (kind == "image") {
      const cv::Mat grey(1024, 1280, CV_8UC1, cv::Scalar(128));
      rc = Run<RosImage>(false, "rt/probe/image", count, period_ms,
                         [&] { return ToMono8Image(grey, 0.0, "camera"); });
    }
    int status = 0;
    waitpid(pid, &status, 0);
    return rc != 0 ? rc : (WIFEXITED(status) ? WEXITSTATUS(status) : 1);
  }
  if (kind == "odometry") return Receive<RosOdometry>("rt/probe/odom", count);
  if (kind == "scan") return Receive<RosLaserScan>("rt/probe/scan", count);
  if (kind == "image") return Receive<RosImage>("rt/probe/image", count);
  return 2;
}
