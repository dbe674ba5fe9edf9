#include "localize_walls.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "groundline/localization/atlas_walls.h"
#include "groundline/sim/wall_faces.h"
#include "groundline/sim/world.h"
#include "groundline/sim/zones.h"

namespace groundline::tools {
namespace {

namespace lidar = localization::lidar;

// The rebuilt world's markings are the dataset's floor map.
bool SameMarkings(const sim::World& world, const core::FloorMap& map) {
  if (world.markings.size() != map.markings.size()) return false;
  for (std::size_t i = 0; i < map.markings.size(); ++i) {
    const auto& a = world.markings[i].polyline_m;
    const auto& b = map.markings[i].polyline_m;
    if (a.size() != b.size()) return false;
    for (std::size_t k = 0; k < a.size(); ++k) {
      if ((a[k] - b[k]).norm() > 1e-6) return false;
    }
  }
  return true;
}

double Mean(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += x;
  return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
}

double Rms(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += x * x;
  return v.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(v.size()));
}

}  // namespace

core::Result<std::vector<localization::WallSegment>> SimulatedWallSegments(
    const core::Dataset& dataset) {
  const auto& provenance = dataset.manifest.provenance;
  const auto generator = provenance.find("generator");
  const auto zone = provenance.find("zone");
  const auto seed = provenance.find("seed");
  if (generator == provenance.end() || generator->second != "groundline sim" ||
      zone == provenance.end() || seed == provenance.end()) {
    return core::Status::Error(
        "wall lines need the site's wall faces: this dataset is not from the simulator "
        "(manifest provenance generator/zone/seed); use --no-wall-lines");
  }
  core::Result<sim::Zone> parsed = sim::ParseZone(zone->second);
  if (!parsed.ok()) return core::Status::Error("manifest provenance zone: " + parsed.message());
  core::Result<sim::World> world = sim::BuildZone(*parsed, std::stoull(seed->second));
  if (!world.ok()) return world.status();
  if (!dataset.floor_map || !SameMarkings(*world, *dataset.floor_map)) {
    return core::Status::Error(
        "the zone " + zone->second + " world of seed " + seed->second +
        " (default options) does not reproduce the dataset's floor map, so its wall faces "
        "would not be the dataset's either (made from a scenario file?); use --no-wall-lines");
  }
  sim::WallFaceOptions options;
  if (dataset.manifest.lidar) options.plane_height_m = dataset.manifest.lidar->mount_height_m;
  std::vector<localization::WallSegment> segments;
  for (const sim::WallFace& face : sim::WallFaces(*world, options)) {
    segments.push_back({face.a_m, face.b_m, face.rack_face});
  }
  return segments;
}

WallLineSource::WallLineSource(const core::Dataset& dataset, const localization::Atlas& atlas,
                               const localization::AssociationOptions& association)
    : association_(association), ground_truth_(dataset.ground_truth) {
  for (const localization::AtlasLine& line : atlas.lines) {
    if (core::IsFaceKind(line.kind)) walls_.lines.push_back(line);
  }
  if (dataset.manifest.lidar && dataset.manifest.lidar->rate_hz > 0.0) {
    time_increment_s_ = 1.0 / (dataset.manifest.lidar->rate_hz * 2.0 * std::numbers::pi);
  }
}

std::vector<localization::LineObservation> WallLineSource::Observe(
    const LidarKeyframeSource& source, double stamp_s, const localization::PoseEstimate& predicted,
    nlohmann::ordered_json* health_line) {
  ++keyframes_;
  const core::LaserScan* scan = source.ScanNearest(stamp_s);
  if (scan == nullptr) return {};
  // A rotating mirror: one revolution per scan period, rays in angle order.
  const double time_increment_s = time_increment_s_ * std::abs(scan->angle_increment_rad);
  const std::vector<lidar::RangePoint> points = lidar::RangePointsAt(
      scan->ranges_m, scan->angle_min_rad, scan->angle_increment_rad, scan->stamp_s,
      time_increment_s, source.T_base_lidar(), source.OdometryAt(stamp_s),
      [&source](double t) { return source.OdometryAt(t); },
      std::max(options_.min_range_m, scan->range_min_m),
      std::min(options_.max_range_m, scan->range_max_m));
  const std::vector<lidar::WallLine> walls = lidar::ExtractWallLines(points, options_);
  std::vector<localization::LineObservation> observations = lidar::WallLineObservations(walls);
  const std::vector<localization::Match> matches = localization::AssociateLines(
      observations, walls_, predicted.T_map_base, predicted.covariance, association_);
  int used = 0, ambiguous = 0;
  for (const localization::Match& match : matches) {
    ambiguous += match.ambiguous;
    if (match.landmark < 0) continue;
    ++used;
    if (ground_truth_.empty()) continue;
    const core::SE2 truth = sim::InterpolatePose(ground_truth_, stamp_s);
    const localization::LineObservation& z = observations[match.observation];
    const Eigen::Vector2d nu = perception::LineDifference(
        perception::InverseTransformLine(truth, walls_.lines[match.landmark].line_map),
        z.line_base);
    rho_residual_m_.push_back(nu(0));
    alpha_residual_rad_.push_back(nu(1));
    d2_.push_back(nu.dot(z.covariance.ldlt().solve(nu)));
    recessed_.push_back(walls[match.observation].recessed);
  }
  const int n = static_cast<int>(observations.size());
  observed_ += n;
  used_ += used;
  rejected_ += n - used;
  ambiguous_ += ambiguous;
  (*health_line)["walls_observed"] = n;
  (*health_line)["walls_used"] = used;
  (*health_line)["walls_rejected"] = n - used;
  return observations;
}

nlohmann::ordered_json WallLineSource::Summary() const {
  nlohmann::ordered_json out;
  out["atlas_wall_lines"] = walls_.lines.size();
  out["keyframes"] = keyframes_;
  out["observed"] = observed_;
  out["used"] = used_;
  out["rejected"] = rejected_;
  out["ambiguous"] = ambiguous_;
  // All used walls, then those whose offset came from the band's centre
  // (plain walls) and from its front (recessed: rack faces).
  for (const auto& [key, which] : {std::pair("at_truth", -1), std::pair("at_truth_centre", 0),
                                   std::pair("at_truth_recessed", 1)}) {
    std::vector<double> rho, alpha, d2;
    for (std::size_t k = 0; k < rho_residual_m_.size(); ++k) {
      if (which >= 0 && recessed_[k] != (which == 1)) continue;
      rho.push_back(rho_residual_m_[k]);
      alpha.push_back(alpha_residual_rad_[k]);
      d2.push_back(d2_[k]);
    }
    if (rho.empty()) continue;
    out[key] = {{"count", rho.size()},         {"rho_mean_m", Mean(rho)},
                {"rho_rms_m", Rms(rho)},       {"alpha_mean_rad", Mean(alpha)},
                {"alpha_rms_rad", Rms(alpha)}, {"mahalanobis2_mean", Mean(d2)}};
  }
  return out;
}

}  // namespace groundline::tools
