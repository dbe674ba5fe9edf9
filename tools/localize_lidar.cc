#include "localize_lidar.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>

#include "groundline/core/atomic_file.h"
#include "groundline/core/trajectory_io.h"
#include "groundline/core/trajectory_metrics.h"
#include "groundline/localization/dead_reckoning.h"
#include "groundline/localization/keyframe_selector.h"
#include "groundline/sim/world.h"
#include "progress.h"
#include "run_summary.h"

namespace groundline::tools {
namespace {

namespace fs = std::filesystem;
namespace lidar = localization::lidar;

int Fail(const std::string& message) {
  std::fprintf(stderr, "groundline localize: %s\n", message.c_str());
  return 1;
}

// The simulated zone the dataset was generated in, if any (the regions' layout).
std::optional<sim::Zone> SimulatedZone(const core::DatasetManifest& manifest) {
  const auto generator = manifest.provenance.find("generator");
  const auto zone = manifest.provenance.find("zone");
  if (generator == manifest.provenance.end() || generator->second != "groundline sim" ||
      zone == manifest.provenance.end()) {
    return std::nullopt;
  }
  core::Result<sim::Zone> parsed = sim::ParseZone(zone->second);
  return parsed.ok() ? std::optional(*parsed) : std::nullopt;
}

// Datasets from `groundline sim` before it stamped scans at the middle of the
// sweep (docs/dataset.md; its provenance then says lidar_stamp: mid_sweep)
// stamp the first ray: their scans describe a time half a sweep later.
bool StampsFirstRay(const core::DatasetManifest& manifest) {
  const auto generator = manifest.provenance.find("generator");
  const auto stamp = manifest.provenance.find("lidar_stamp");
  return generator != manifest.provenance.end() && generator->second == "groundline sim" &&
         (stamp == manifest.provenance.end() || stamp->second != "mid_sweep");
}

}  // namespace

struct LidarKeyframeSource::Impl {
  explicit Impl(core::LaserScanReader r) : reader(std::move(r)) {}

  core::LaserScanReader reader;
  std::optional<core::LaserScan> pending;
  std::optional<core::LaserScan> last;  // the last scan fed to the odometry
  bool done = false;
  core::SE2 T_base_lidar;
  double lidar_rate_hz = 0.0;
  bool stamps_first_ray = false;
  core::Trajectory odometry;  // T_map_base per encoder reading
  core::Trajectory ground_truth;
  std::optional<sim::Zone> zone;
  lidar::ScanPointsOptions points_options;
  lidar::ScanOdometry scan_odometry{lidar::ScanOdometryOptions()};
  long matched = 0, keyframes = 0, degenerate = 0, with_relative = 0;
  long fisher_degenerate = 0, aliased = 0;
  // Per region: keyframes, flagged degenerate, Fisher-degenerate, aliased.
  std::map<std::string, std::array<long, 4>> regions;
};

LidarKeyframeSource::LidarKeyframeSource(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
LidarKeyframeSource::~LidarKeyframeSource() = default;

core::Result<std::unique_ptr<LidarKeyframeSource>> LidarKeyframeSource::Open(
    const fs::path& dir, const core::Dataset& dataset, const core::StampedPose& start) {
  const core::DatasetManifest& manifest = dataset.manifest;
  if (!manifest.lidar || manifest.files.lidar_scans.empty()) {
    return core::Status::Error(dir.string() + ": the LiDAR modes need lidar_scans (no LiDAR)");
  }
  if (!manifest.wheel_encoders || dataset.wheel_encoders.empty()) {
    return core::Status::Error(dir.string() + ": the LiDAR modes need wheel encoder readings");
  }
  core::Result<core::LaserScanReader> reader =
      core::LaserScanReader::Open(dir / manifest.files.lidar_scans);
  if (!reader.ok()) return reader.status();
  localization::DeadReckoningOptions options;
  options.drive.wheel_radius_m = manifest.wheel_encoders->wheel_radius_m;
  options.drive.track_m = manifest.wheel_encoders->track_m;
  core::StampedPose initial = start;
  initial.covariance.reset();
  core::Result<localization::DeadReckoningResult> odometry =
      localization::DeadReckon(dataset.wheel_encoders, initial, options);
  if (!odometry.ok()) return core::Status::Error(dir.string() + ": " + odometry.message());
  auto impl = std::make_unique<Impl>(std::move(*reader));
  impl->T_base_lidar = manifest.lidar->T_base_lidar;
  impl->lidar_rate_hz = manifest.lidar->rate_hz;
  impl->stamps_first_ray = StampsFirstRay(manifest);
  impl->odometry = std::move(odometry->odometry_rate);
  impl->ground_truth = dataset.ground_truth;
  impl->zone = SimulatedZone(manifest);
  return std::unique_ptr<LidarKeyframeSource>(new LidarKeyframeSource(std::move(impl)));
}

core::SE2 LidarKeyframeSource::OdometryAt(double stamp_s) const {
  return sim::InterpolatePose(impl_->odometry, stamp_s);
}

const core::LaserScan* LidarKeyframeSource::ScanNearest(double stamp_s) const {
  const Impl& m = *impl_;
  if (m.last && m.pending) {
    return stamp_s - m.last->stamp_s <= m.pending->stamp_s - stamp_s ? &*m.last : &*m.pending;
  }
  return m.last ? &*m.last : (m.pending ? &*m.pending : nullptr);
}

const core::SE2& LidarKeyframeSource::T_base_lidar() const { return impl_->T_base_lidar; }

core::Result<lidar::ScanOdometryKeyframe> LidarKeyframeSource::KeyframeAt(double stamp_s) {
  Impl& m = *impl_;
  while (true) {
    if (!m.pending && !m.done) {
      core::LaserScan scan;
      core::Result<bool> read = m.reader.Next(&scan);
      if (!read.ok()) return read.status();
      if (*read) {
        m.pending = std::move(scan);
      } else {
        m.done = true;
      }
    }
    if (!m.pending) break;
    const core::LaserScan& s = *m.pending;
    // The scan describes the middle of its sweep (scan_odometry.h).
    const double scan_s =
        s.stamp_s +
        lidar::MidSweepOffsetS(s.ranges_m.size(), s.angle_increment_rad, m.lidar_rate_hz);
    if (scan_s > stamp_s) break;
    if (scan_s > m.odometry.front().stamp_s) {
      const lidar::ScanPoints points =
          lidar::ScanPointsFromRanges(s.ranges_m, s.angle_min_rad, s.angle_increment_rad,
                                      s.range_max_m, m.T_base_lidar, m.points_options);
      core::Result<lidar::ScanReport> report =
          m.scan_odometry.AddScan(scan_s, OdometryAt(scan_s), points);
      if (!report.ok()) {
        return core::Status::Error(m.reader.file() + " line " + std::to_string(m.reader.line()) +
                                   ": " + report.message());
      }
      m.matched += report->matched;
    }
    m.last = std::move(m.pending);
    m.pending.reset();
  }
  return m.scan_odometry.Keyframe(stamp_s, OdometryAt(stamp_s));
}

void LidarKeyframeSource::AddHealth(const lidar::ScanOdometryKeyframe& k,
                                    nlohmann::ordered_json* line) {
  Impl& m = *impl_;
  const lidar::MatchInformation& info = k.information;
  (*line)["lidar_matched"] = k.matched;
  (*line)["lidar_score"] = k.match_score;
  (*line)["lidar_degenerate"] = k.degenerate;
  (*line)["lidar_fisher_degenerate"] = info.degenerate;
  (*line)["lidar_aliased"] = k.aliasing.aliased;
  (*line)["lidar_alias_score"] = k.aliasing.best_score;
  (*line)["lidar_alias_shift_m"] = k.aliasing.best_shift_m;
  (*line)["lidar_alias_evidence"] = k.aliasing.evidence;
  (*line)["lidar_rank"] = info.rank;
  (*line)["lidar_scaled_eigenvalues"] = {info.scaled_eigenvalues(0), info.scaled_eigenvalues(1),
                                         info.scaled_eigenvalues(2)};
  const core::Vector3& v = info.weakest_direction;
  (*line)["lidar_weakest_direction"] = {v(0), v(1), v(2)};
  const core::Vector2 v_map = k.T_odom_base.Rotation() * core::Vector2(v.head<2>());
  (*line)["lidar_weakest_direction_map"] = {v_map.x(), v_map.y(), v(2)};
  (*line)["lidar_relative_rank"] = k.relative_rank;
  if (k.relative) {
    // The measurement and its (scaled) square-root information, row-major:
    // enough to check its consistency against ground truth offline.
    const core::SE2& Z = k.relative->T_prev_curr;
    const core::Matrix3& S = k.relative->sqrt_information;
    (*line)["lidar_relative"] = {Z.x(), Z.y(), Z.yaw()};
    (*line)["lidar_relative_sqrt_information"] = {S(0, 0), S(0, 1), S(0, 2), S(1, 0), S(1, 1),
                                                  S(1, 2), S(2, 0), S(2, 1), S(2, 2)};
  }
  ++m.keyframes;
  m.degenerate += k.degenerate;
  m.fisher_degenerate += info.degenerate;
  m.aliased += k.aliasing.aliased;
  m.with_relative += k.relative.has_value();
  if (m.zone && !m.ground_truth.empty()) {
    const core::SE2 truth = sim::InterpolatePose(m.ground_truth, k.stamp_s);
    const std::string region =
        sim::ZoneRegionName(sim::PresetRegionAt(*m.zone, truth.translation(), kRegionEndMarginM));
    (*line)["region"] = region;
    std::array<long, 4>& counts = m.regions[region];
    counts[0] += 1;
    counts[1] += k.degenerate;
    counts[2] += info.degenerate;
    counts[3] += k.aliasing.aliased;
  }
}

nlohmann::ordered_json LidarKeyframeSource::Summary() const {
  const Impl& m = *impl_;
  nlohmann::ordered_json out;
  out["n_scans"] = m.scan_odometry.num_scans();
  out["n_scans_matched"] = m.matched;
  out["n_keyframes"] = m.keyframes;
  out["n_keyframes_degenerate"] = m.degenerate;
  out["n_keyframes_fisher_degenerate"] = m.fisher_degenerate;
  out["n_keyframes_aliased"] = m.aliased;
  out["n_keyframes_with_relative"] = m.with_relative;
  nlohmann::ordered_json regions;
  for (const auto& [name, counts] : m.regions) {
    const double n = static_cast<double>(counts[0]);
    regions[name] = {{"keyframes", counts[0]},
                     {"flagged_degenerate", counts[1]},
                     {"fraction_flagged", static_cast<double>(counts[1]) / n},
                     {"fraction_fisher_degenerate", static_cast<double>(counts[2]) / n},
                     {"fraction_aliased", static_cast<double>(counts[3]) / n}};
  }
  if (!regions.empty()) {
    out["region_end_margin_m"] = kRegionEndMarginM;
    out["detector"] = regions;
  }
  return out;
}

int RunLocalizeLidar(const LocalizeLinesFlags& flags) {
  const RunClock clock;
  core::DatasetReadOptions read_options;
  read_options.load_images = false;
  read_options.check_image_files = false;
  read_options.load_scans = false;  // streamed
  core::Result<core::Dataset> dataset = core::ReadDataset(flags.dataset_dir, read_options);
  if (!dataset.ok()) return Fail(dataset.message());
  if (dataset->wheel_encoders.empty()) return Fail(flags.dataset_dir + ": no encoder readings");
  core::StampedPose start{dataset->wheel_encoders.front().stamp_s, core::SE2(), std::nullopt};
  if (flags.initial_pose.size() == 3) {
    start.pose = core::SE2(flags.initial_pose[0], flags.initial_pose[1],
                           flags.initial_pose[2] * std::numbers::pi / 180.0);
  } else if (!dataset->ground_truth.empty()) {
    start = dataset->ground_truth.front();
  }
  core::Result<std::unique_ptr<LidarKeyframeSource>> source =
      LidarKeyframeSource::Open(flags.dataset_dir, *dataset, start);
  if (!source.ok()) return Fail(source.message());

  const localization::KeyframeSelector selector{localization::KeyframeSelector::Options()};
  core::Trajectory keyframes{{start.stamp_s, start.pose, std::nullopt}};
  std::ostringstream health;
  core::SE2 T_odom_keyframe = start.pose;
  ProgressLine progress("[localize]");
  const std::vector<core::WheelEncoderReading>& readings = dataset->wheel_encoders;
  for (std::size_t i = 0; i < readings.size(); ++i) {
    const double stamp_s = readings[i].stamp_s;
    if (stamp_s <= start.stamp_s) continue;
    if (i % 1000 == 0) progress.Update("replay", static_cast<double>(i) / readings.size());
    const core::SE2 T_odom_base = (*source)->OdometryAt(stamp_s);
    if (!selector.IsKeyframeDue(T_odom_keyframe.Between(T_odom_base))) continue;
    T_odom_keyframe = T_odom_base;
    core::Result<lidar::ScanOdometryKeyframe> k = (*source)->KeyframeAt(stamp_s);
    if (!k.ok()) return Fail(k.message());
    nlohmann::ordered_json line;
    line["keyframe"] = keyframes.size();
    line["stamp_s"] = stamp_s;
    line["x_m"] = k->T_odom_base.x();
    line["y_m"] = k->T_odom_base.y();
    line["yaw_deg"] = k->T_odom_base.yaw() * 180.0 / std::numbers::pi;
    line["mode"] = "lidar";
    (*source)->AddHealth(*k, &line);
    health << line.dump() << "\n";
    keyframes.push_back({stamp_s, k->T_odom_base, std::nullopt});
  }
  progress.Update("replay", 1.0);

  const fs::path out(flags.out_dir);
  for (const core::Status& s : {core::WriteTumTrajectory(out / "trajectory.tum", keyframes),
                                core::WriteFileAtomically(out / "health.jsonl", health.str())}) {
    if (!s.ok()) return Fail(s.message());
  }
  nlohmann::ordered_json summary;
  summary["dataset"] = flags.dataset_dir;
  summary["mode"] = "lidar";
  summary["lidar"] = (*source)->Summary();
  std::printf("%s: %zu keyframes; LiDAR %s\n", flags.dataset_dir.c_str(), keyframes.size(),
              summary["lidar"].dump().c_str());
  if (core::Status s = FinishRunSummary(keyframes, dataset->ground_truth, clock, out, &summary);
      !s.ok()) {
    return Fail(s.message());
  }
  return 0;
}

}  // namespace groundline::tools
