// io_dds_listener: subscribes to the standard groundline input topics
// through DdsInputs and prints what arrived per topic (a check of a replay or
// a robot's topics before the service is pointed at them). Exits once no message came for --idle
// seconds after the first one, or after --timeout seconds.
//   io_dds_listener [--idle S] [--timeout S] [--lossless]
// Exit codes: 0 odometry, joint states and scans received; 1 something
// missing or a DDS failure; 2 usage.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "groundline/io/dds_inputs.h"

namespace {

using namespace groundline;

int Run(double idle_s, double timeout_s, bool lossless) {
  core::Result<io::DdsParticipant> participant = io::DdsParticipant::Create();
  if (!participant.ok()) {
    std::fprintf(stderr, "io_dds_listener: %s\n", participant.message().c_str());
    return 1;
  }
  double travelled_m = 0.0, last_x = 0.0, last_y = 0.0, last_wheel_rad = 0.0;
  std::size_t beams = 0;
  bool have_odom = false;
  io::DdsInputCallbacks cb;
  cb.on_odometry = [&](const io::PlanarOdometry& o) {
    if (have_odom)
      travelled_m += std::hypot(o.T_odom_base.x() - last_x, o.T_odom_base.y() - last_y);
    last_x = o.T_odom_base.x();
    last_y = o.T_odom_base.y();
    have_odom = true;
  };
  cb.on_wheels = [&](const core::WheelEncoderReading& w) { last_wheel_rad += w.left_delta_rad; };
  cb.on_scan = [&](const core::LaserScan& s) { beams += s.ranges_m.size(); };
  cb.on_image = [&](double, const cv::Mat&) {};
  io::DdsInputsOptions options;
  options.stamp_reference = io::StampReference::kNone;  // dataset or wall stamps alike
  options.camera_frame.clear();
  if (lossless) options.sensor_qos = io::QosPreset::kLossless;
  core::Result<io::DdsInputs> inputs = io::DdsInputs::Create(*participant, options, cb);
  if (!inputs.ok()) {
    std::fprintf(stderr, "io_dds_listener: %s\n", inputs.message().c_str());
    return 1;
  }
  std::printf("io_dds_listener: listening on domain %u (%s configuration)\n",
              participant->domain_id(), participant->config_source().c_str());
  std::fflush(stdout);
  const auto start = std::chrono::steady_clock::now();
  auto last_message = start;
  bool any = false;
  for (;;) {
    core::Result<int> n = inputs->Poll(std::chrono::milliseconds(100));
    if (!n.ok()) {
      std::fprintf(stderr, "io_dds_listener: %s\n", n.message().c_str());
      return 1;
    }
    const auto now = std::chrono::steady_clock::now();
    if (*n > 0) {
      any = true;
      last_message = now;
    }
    if (any && std::chrono::duration<double>(now - last_message).count() > idle_s) break;
    if (std::chrono::duration<double>(now - start).count() > timeout_s) break;
  }
  bool complete = true;
  for (int i = 0; i < io::kNumDdsInputs; ++i) {
    const auto which = static_cast<io::DdsInput>(i);
    const io::DdsInputCounters& c = inputs->counters(which);
    std::printf("  %-13s received %6llu  accepted %6llu  dropped %4llu%s%s\n",
                io::DdsInputName(which), static_cast<unsigned long long>(c.received),
                static_cast<unsigned long long>(c.accepted),
                static_cast<unsigned long long>(c.dropped), c.dropped ? "  last: " : "",
                c.last_drop_reason.c_str());
    const bool required = which == io::DdsInput::kOdometry || which == io::DdsInput::kJointState ||
                          which == io::DdsInput::kScan;
    if (required && c.accepted == 0) complete = false;
  }
  std::printf("  odometry path %.3f m, left wheel turned %.3f rad, %zu beams\n", travelled_m,
              last_wheel_rad, beams);
  return complete ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  double idle_s = 3.0, timeout_s = 600.0;
  bool lossless = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--idle") == 0 && i + 1 < argc) {
      idle_s = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--timeout") == 0 && i + 1 < argc) {
      timeout_s = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--lossless") == 0) {
      lossless = true;
    } else {
      std::fprintf(stderr, "usage: io_dds_listener [--idle S] [--timeout S] [--lossless]\n");
      return 2;
    }
  }
  return Run(idle_s, timeout_s, lossless);
}
