// `groundline replay-dds DATASET`: publishes a dataset's sensor streams as
// ROS 2 topics over DDS, in the dataset's time order (core/dataset_streams.h,
// paced by service::ReplayEvents), at real time or a multiple of it. Scans
// are stamped at their first ray, as ROS does (the dataset may stamp them
// mid-sweep). Odometry is integrated causally from the wheel encoders
// with the project's differential-drive model (OdometryIntegrator), as a
// robot's base driver would publish it.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numbers>
#include <optional>
#include <string>

#include <opencv2/imgcodecs.hpp>

#include "commands.h"
#include "groundline/core/dataset.h"
#include "groundline/core/dataset_streams.h"
#include "groundline/io/dds_convert.h"
#include "groundline/io/dds_convert_sensors.h"
#include "groundline/io/dds_pubsub.h"
#include "groundline/localization/lidar/scan_odometry.h"
#include "groundline/localization/odometry_integrator.h"
#include "groundline/service/replay.h"

namespace groundline::tools {
namespace {

struct ReplayFlags {
  std::string dir;
  double rate = 1.0;
  std::string odometry = "both";  // odom | joint-states | both | none
  bool images = false;
  bool no_scans = false;
  std::string stamps = "wall";  // wall | dataset
  std::string lidar_frame = "laser";
  std::string camera_frame = "camera_optical";
  std::string left_joint = "left_wheel_joint";
  std::string right_joint = "right_wheel_joint";
  double wait_for_subscribers_s = 0.0;
  bool lossless = false;
  std::string ros_namespace;  // "agv7": topics /agv7/odom, ...
};

// The publishers of one replay; empty optionals are streams not published.
struct Publishers {
  std::optional<io::DdsPublisher<io::RosOdometry>> odom;
  std::optional<io::DdsPublisher<io::RosJointState>> joints;
  std::optional<io::DdsPublisher<io::RosLaserScan>> scan;
  std::optional<io::DdsPublisher<io::RosImage>> image;
  std::optional<io::DdsPublisher<io::RosTfMessage>> tf_static;
};

template <typename T>
core::Status Make(const io::DdsParticipant& p, const std::string& topic, io::QosPreset qos,
                  std::optional<io::DdsPublisher<T>>* out) {
  core::Result<io::DdsPublisher<T>> pub = io::DdsPublisher<T>::Create(p, topic, qos);
  if (!pub.ok()) return pub.status();
  out->emplace(std::move(*pub));
  return core::Status::Ok();
}

int RunReplay(const ReplayFlags& f) {
  core::DatasetReadOptions read;
  read.load_images = f.images;
  read.check_image_files = f.images;
  read.load_scans = false;         // streamed (core/dataset_streams.h)
  read.load_ground_truth = false;  // a replay is what a robot would send: no ground truth
  read.load_floor_map = false;
  core::Result<core::Dataset> dataset = core::ReadDataset(f.dir, read);
  if (!dataset.ok()) {
    std::fprintf(stderr, "replay-dds: %s\n", dataset.message().c_str());
    return 1;
  }
  const core::Dataset& d = *dataset;
  const core::DatasetManifest& m = d.manifest;
  if (f.odometry != "none" && !m.wheel_encoders) {
    std::fprintf(stderr, "replay-dds: %s has no wheel encoders; use --odometry none\n",
                 f.dir.c_str());
    return 1;
  }
  if (f.images && !m.camera) {
    std::fprintf(stderr, "replay-dds: %s has no camera; drop --images\n", f.dir.c_str());
    return 1;
  }
  localization::DiffDriveParams drive;
  if (m.wheel_encoders) {
    drive.wheel_radius_m = m.wheel_encoders->wheel_radius_m;
    drive.track_m = m.wheel_encoders->track_m;
  }
  localization::OdometryIntegrator integrator(drive, localization::OdometryNoiseParams{});

  core::Result<io::DdsParticipant> participant = io::DdsParticipant::Create();
  if (!participant.ok()) {
    std::fprintf(stderr, "replay-dds: %s\n", participant.message().c_str());
    return 1;
  }
  const std::string topic_prefix =
      f.ros_namespace.empty() ? std::string("rt/") : "rt/" + f.ros_namespace + "/";
  // Reliable writers match both reliable and best-effort ROS 2 readers.
  const io::QosPreset qos = f.lossless ? io::QosPreset::kLossless : io::QosPreset::kDefault;
  Publishers pub;
  core::Status made = core::Status::Ok();
  if (f.odometry == "odom" || f.odometry == "both")
    made = Make(*participant, topic_prefix + "odom", qos, &pub.odom);
  if (made.ok() && (f.odometry == "joint-states" || f.odometry == "both")) {
    made = Make(*participant, topic_prefix + "joint_states", qos, &pub.joints);
  }
  if (made.ok() && !f.no_scans && m.lidar)
    made = Make(*participant, topic_prefix + "scan", qos, &pub.scan);
  if (made.ok() && f.images)
    made = Make(*participant, topic_prefix + "camera/image_raw", qos, &pub.image);
  if (made.ok() && m.lidar)
    made = Make(*participant, topic_prefix + "tf_static", io::QosPreset::kTfStatic, &pub.tf_static);
  if (!made.ok()) {
    std::fprintf(stderr, "replay-dds: %s\n", made.message().c_str());
    return 1;
  }
  if (f.stamps == "wall" && f.rate != 1.0) {
    std::fprintf(stderr,
                 "replay-dds: warning: wall-clock stamps at --rate %g run %s the clock; "
                 "consider --stamps dataset\n",
                 f.rate, f.rate > 1.0 ? "ahead of" : "behind");
  }
  std::printf("replay-dds: %s on DDS domain %u (%s configuration), rate %gx, %s stamps\n",
              f.dir.c_str(), participant->domain_id(), participant->config_source().c_str(), f.rate,
              f.stamps.c_str());
  if (f.wait_for_subscribers_s > 0.0) {
    // Every sensor topic: a subscriber that matched one topic may not have
    // matched the others yet.
    const auto timeout =
        std::chrono::milliseconds(static_cast<long>(1000 * f.wait_for_subscribers_s));
    for (const io::DdsEntity* w :
         {pub.odom ? &pub.odom->writer() : nullptr, pub.joints ? &pub.joints->writer() : nullptr,
          pub.scan ? &pub.scan->writer() : nullptr, pub.image ? &pub.image->writer() : nullptr}) {
      if (w != nullptr && !io::WaitForMatches(*w, true, 1, timeout)) {
        std::fprintf(stderr, "replay-dds: no subscriber within %g s\n", f.wait_for_subscribers_s);
        return 1;
      }
    }
  }

  core::DatasetStreamOptions streamed;
  streamed.wheels = f.odometry != "none";
  streamed.scans = !f.no_scans && m.lidar.has_value();
  streamed.frames = f.images;
  core::Result<core::DatasetStreams> streams = core::DatasetStreams::Open(f.dir, d, streamed);
  if (!streams.ok()) {
    std::fprintf(stderr, "replay-dds: %s\n", streams.message().c_str());
    return 1;
  }
  // ROS stamps a LaserScan at its first ray; the dataset may stamp mid-sweep.
  const double lidar_rate_hz = m.lidar ? m.lidar->rate_hz : 0.0;
  const bool mid_sweep = m.lidar && m.lidar->stamp == core::LidarStamp::kMidSweep;
  std::optional<double> first_stamp_s;
  double wall_start_s = 0.0;
  auto out_stamp = [&](double s) {
    return f.stamps == "wall" ? wall_start_s + (s - *first_stamp_s) : s;
  };
  double left_rad = 0.0, right_rad = 0.0, prev_wheel_stamp_s = 0.0;
  std::size_t sent_wheels = 0, sent_scans = 0, sent_images = 0;
  core::Status failed = core::Status::Ok();
  service::ReplayOptions paced;
  paced.speed = f.rate;
  paced.stop = [&failed] { return !failed.ok(); };
  const core::Result<service::ReplayStats> stats =
      service::ReplayEvents(*streams, paced, [&](core::DatasetEvent& e) {
        if (!first_stamp_s) {
          first_stamp_s = e.stamp_s;
          wall_start_s =
              std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch())
                  .count();
          if (f.stamps == "wall") {
            std::printf("replay-dds: stamps are the dataset's plus %.9f s\n",
                        wall_start_s - *first_stamp_s);
            std::fflush(stdout);
          }
          if (pub.tf_static) {
            const core::Status s =
                pub.tf_static->Write(io::ToTfMessage({{out_stamp(e.stamp_s), m.frames.base_link,
                                                       f.lidar_frame, m.lidar->T_base_lidar}})
                                         .msg());
            if (!s.ok()) std::fprintf(stderr, "replay-dds: %s\n", s.message().c_str());
          }
        }
        const double stamp = out_stamp(e.stamp_s);
        core::Status s = core::Status::Ok();
        switch (e.kind) {
          case core::DatasetEvent::Kind::kWheel: {
            const core::WheelEncoderReading& r = e.wheel;
            io::PlanarOdometry odom;
            odom.stamp_s = stamp;
            odom.odom_frame = m.frames.odom;
            odom.base_frame = m.frames.base_link;
            // The first reading's deltas predate the file (docs/dataset.md): not applied.
            if (sent_wheels > 0) {
              const localization::OdometryIncrement inc =
                  integrator.Integrate({r.left_delta_rad, r.right_delta_rad});
              const double dt = r.stamp_s - prev_wheel_stamp_s;
              left_rad += r.left_delta_rad;
              right_rad += r.right_delta_rad;
              if (dt > 0.0) {
                odom.forward_velocity_mps = inc.distance_m / dt;
                odom.yaw_rate_radps = inc.rotation_rad / dt;
                odom.twist_covariance = inc.covariance / (dt * dt);
              }
            }
            prev_wheel_stamp_s = r.stamp_s;
            odom.T_odom_base = integrator.T_odom_base();
            odom.covariance = integrator.covariance();
            if (pub.odom) s = pub.odom->Write(io::ToOdometry(odom).msg());
            if (s.ok() && pub.joints) {
              io::WheelJointState js;
              js.stamp_s = stamp;
              js.names = {f.left_joint, f.right_joint};
              js.position_rad = {left_rad, right_rad};
              s = pub.joints->Write(io::ToJointState(js).msg());
            }
            ++sent_wheels;
            break;
          }
          case core::DatasetEvent::Kind::kScan: {
            if (!pub.scan) break;
            core::LaserScan scan = std::move(e.scan);
            const double sweep_s = localization::lidar::MidSweepOffsetS(
                scan.ranges_m.size(), scan.angle_increment_rad, lidar_rate_hz);
            scan.stamp_s = stamp - (mid_sweep ? sweep_s : 0.0);
            io::DdsSample<io::RosLaserScan> msg =
                io::ToLaserScan(scan, f.lidar_frame, 1.0 / lidar_rate_hz);
            // One mirror revolution per scan: the time between two rays.
            msg.msg().time_increment = static_cast<float>(std::abs(scan.angle_increment_rad) /
                                                          (2.0 * std::numbers::pi * lidar_rate_hz));
            s = pub.scan->Write(msg.msg());
            ++sent_scans;
            break;
          }
          case core::DatasetEvent::Kind::kFrame: {
            const cv::Mat grey = cv::imread(e.image_path.string(), cv::IMREAD_GRAYSCALE);
            if (grey.empty()) {
              s = core::Status::Error("cannot read image " + e.image_path.string());
              break;
            }
            s = pub.image->Write(io::ToMono8Image(grey, stamp, f.camera_frame).msg());
            ++sent_images;
            break;
          }
        }
        if (!s.ok()) failed = s;
      });
  if (!stats.ok()) failed = stats.status();
  if (!failed.ok()) {
    std::fprintf(stderr, "replay-dds: %s\n", failed.message().c_str());
    return 1;
  }
  if (stats->events == 0) {
    std::printf("replay-dds: nothing to publish\n");
    return 0;
  }
  std::printf(
      "replay-dds: published %zu wheel readings, %zu scans, %zu images over %.3f s of data\n",
      sent_wheels, sent_scans, sent_images, stats->last_stamp_s - stats->first_stamp_s);
  std::fflush(stdout);
  // Reliable data still in flight is lost if the participant goes at once
  // (keep-all writers: a reader slowed by its host may take longer to acknowledge).
  for (const io::DdsEntity* w :
       {pub.odom ? &pub.odom->writer() : nullptr, pub.joints ? &pub.joints->writer() : nullptr,
        pub.scan ? &pub.scan->writer() : nullptr, pub.image ? &pub.image->writer() : nullptr}) {
    if (w != nullptr) dds_wait_for_acks(w->get(), f.lossless ? DDS_SECS(60) : DDS_SECS(5));
  }
  return 0;
}

}  // namespace

CLI::App* AddReplayDdsCommand(CLI::App& parent, CommandRunner* run) {
  auto f = std::make_shared<ReplayFlags>();
  CLI::App* cmd = parent.add_subcommand(
      "replay-dds", "Publish a dataset's sensor streams as ROS 2 topics over DDS (CycloneDDS)");
  cmd->footer(
      "Topics (ROS 2 Humble types; docs/dds.md):\n"
      "  /odom                nav_msgs/Odometry, odom -> base_link, integrated from the wheels\n"
      "  /joint_states        sensor_msgs/JointState, absolute wheel angles (rad)\n"
      "  /scan                sensor_msgs/LaserScan, stamped at the first ray (no-return beams\n"
      "                       as +inf)\n"
      "  /camera/image_raw    sensor_msgs/Image mono8 (with --images)\n"
      "  /tf_static           base_link -> LiDAR frame (transient local)\n"
      "Domain: ROS_DOMAIN_ID (default 0). Network: CYCLONEDDS_URI when set, otherwise the\n"
      "compiled-in loopback configuration (samples/cyclonedds_loopback.xml): nothing leaves\n"
      "this machine. --stamps wall shifts the dataset's clock to start now (live-like, for\n"
      "--rate 1); --stamps dataset keeps the dataset's stamps (for other rates).\n"
      "Exit code: 0 published, 1 unreadable dataset or DDS failure, 2 usage.\n"
      "Example:\n"
      "  ROS_DOMAIN_ID=7 groundline replay-dds /data/zone_b_seed7 --rate 2 --stamps dataset "
      "--images");
  cmd->add_option("DATASET", f->dir, "dataset directory (the one holding manifest.yaml)")
      ->required();
  cmd->add_option("--rate", f->rate, "playback speed, a multiple of real time (> 0)")
      ->default_val(1.0)
      ->check(CLI::PositiveNumber);
  cmd->add_option("--odometry", f->odometry, "odometry topics: odom, joint-states, both or none")
      ->default_val("both")
      ->check(CLI::IsMember({"odom", "joint-states", "both", "none"}));
  cmd->add_flag("--images", f->images, "also publish the camera images (mono8); default: off");
  cmd->add_flag("--no-scans", f->no_scans, "do not publish the LiDAR scans; default: publish");
  cmd->add_option("--stamps", f->stamps, "message stamps: wall (start now) or dataset")
      ->default_val("wall")
      ->check(CLI::IsMember({"wall", "dataset"}));
  cmd->add_option("--lidar-frame", f->lidar_frame, "frame_id of the scans")->default_val("laser");
  cmd->add_option("--camera-frame", f->camera_frame, "frame_id of the images")
      ->default_val("camera_optical");
  cmd->add_option("--left-joint", f->left_joint, "JointState name of the left wheel")
      ->default_val("left_wheel_joint");
  cmd->add_option("--right-joint", f->right_joint, "JointState name of the right wheel")
      ->default_val("right_wheel_joint");
  cmd->add_option(
         "--wait-for-subscribers", f->wait_for_subscribers_s,
         "wait up to this many seconds for a subscriber before publishing (0: do not wait)")
      ->default_val(0.0)
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--namespace", f->ros_namespace,
                  "ROS namespace of the topics, e.g. agv7 for /agv7/odom; default: none")
      ->check([](const std::string& ns) {
        const bool ok = !ns.empty() && ns.front() != '/' && ns.back() != '/' &&
                        ns.find("//") == std::string::npos;
        return ok ? std::string() : std::string("expected a name without leading/trailing '/'");
      });
  cmd->add_flag("--lossless", f->lossless,
                "keep-all reliable writers (a slow subscriber slows the replay instead of losing "
                "data; not a ROS profile); default: reliable keep-last 10");
  cmd->callback([f, run] { *run = [f] { return RunReplay(*f); }; });
  return cmd;
}

}  // namespace groundline::tools
