// The offset error of the LiDAR wall lines (localization/lidar/wall_lines.h)
// at the true pose, on simulated datasets, split into plain walls and rack
// faces (the issue 6/7 figures).
//   GROUNDLINE_SIM_DATASETS=/work/simdata build/benchmarks/localization_wall_rho_bias
// reads <dir>/{A,B,C,D} (groundline sim datasets with ground truth; a zone
// whose directory is missing is skipped). Every 4th scan is deskewed by the
// ground truth (as the localizer does by the odometry), its faces extracted
// with the default WallLineOptions and each matched to the nearest true face
// of the simulator's world (sim/wall_faces.h) seen from the true pose (within
// 1 deg and 10 cm, sharing some of its extent).
// Counters, per class of the true face (plain: walls, columns, doors; rack:
// a face with rack uprights on it; mixed: the observed segment also spans a
// true face at another offset within 15 cm, as a dock wall with its doors
// recessed 10 cm) and per estimator (unimodal: the offset from the band's
// centre; recessed: from its front; wall_lines.h step 4): n, bias_mm (mean
// of the observed minus the true distance of the face from the LiDAR:
// negative is in front of the face), rms_mm, and z2 (mean squared error over
// the reported rho variance, 1 when consistent).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "groundline/core/dataset.h"
#include "groundline/core/dataset_records.h"
#include "groundline/localization/lidar/wall_lines.h"
#include "groundline/perception/hesse_line.h"
#include "groundline/sim/wall_faces.h"
#include "groundline/sim/world.h"
#include "groundline/sim/zones.h"

namespace groundline::localization {
namespace {

struct Face {
  core::Vector2 a_m, b_m;
  bool rack = false;
};

// The world's faces; a face is a rack face when at least two uprights stand on it.
std::vector<Face> TrueFaces(const sim::World& world, double plane_height_m) {
  sim::WallFaceOptions options;
  options.plane_height_m = plane_height_m;
  std::vector<Face> out;
  for (const sim::WallFace& f : sim::WallFaces(world, options)) {
    const core::Vector2 d = (f.b_m - f.a_m).normalized();
    const double length = (f.b_m - f.a_m).norm();
    int corners = 0;
    for (const sim::Obstacle& o : world.obstacles) {
      if (o.kind != sim::ObstacleKind::kRackUpright) continue;
      for (const core::Vector2& c : o.box.Corners()) {
        const double s = d.dot(c - f.a_m);
        corners +=
            std::abs(f.outward_normal.dot(c - f.a_m)) < 1e-3 && s > -0.01 && s < length + 0.01;
      }
    }
    out.push_back({f.a_m, f.b_m, corners >= 4});
  }
  return out;
}

struct Stats {
  double n = 0, sum = 0, sum2 = 0, z2 = 0;
  void Add(double e, double var) {
    ++n;
    sum += e;
    sum2 += e * e;
    z2 += e * e / var;
  }
};

void Report(benchmark::State& state, const std::string& name, const Stats& s) {
  state.counters[name + "_n"] = s.n;
  if (s.n == 0) return;
  state.counters[name + "_bias_mm"] = 1e3 * s.sum / s.n;
  state.counters[name + "_rms_mm"] = 1e3 * std::sqrt(s.sum2 / s.n);
  state.counters[name + "_z2"] = s.z2 / s.n;
}

void BM_WallRhoBias(benchmark::State& state, const char* zone) {
  const char* root = std::getenv("GROUNDLINE_SIM_DATASETS");
  const std::filesystem::path dir = std::filesystem::path(root ? root : "") / zone;
  if (root == nullptr || !std::filesystem::exists(dir / "manifest.yaml")) {
    state.SkipWithError("set GROUNDLINE_SIM_DATASETS to a directory with the zone's dataset");
    return;
  }
  core::DatasetReadOptions read;
  read.load_images = read.check_image_files = read.load_wheel_encoders = read.load_scans = false;
  const core::Result<core::Dataset> dataset = core::ReadDataset(dir, read);
  if (!dataset.ok() || !dataset->manifest.lidar) {
    state.SkipWithError("cannot read the dataset or it has no LiDAR");
    return;
  }
  const auto& provenance = dataset->manifest.provenance;
  const core::Result<sim::World> world =
      sim::BuildZone(*sim::ParseZone(provenance.at("zone")), std::stoull(provenance.at("seed")));
  const core::LidarSensor& lidar = *dataset->manifest.lidar;
  const std::vector<Face> faces = TrueFaces(*world, lidar.mount_height_m);
  const lidar::WallLineOptions options;
  const auto truth = [&](double t) { return sim::InterpolatePose(dataset->ground_truth, t); };
  Stats plain, rack, mixed, recessed, unimodal;
  for (auto _ : state) {
    core::Result<core::LaserScanReader> reader =
        core::LaserScanReader::Open(dir / dataset->manifest.files.lidar_scans);
    core::LaserScan scan;
    for (long k = 0; [&] {
           const core::Result<bool> more = reader->Next(&scan);
           return more.ok() && *more;
         }();
         ++k) {
      if (k % 4 != 0 || scan.stamp_s < dataset->ground_truth.front().stamp_s ||
          scan.stamp_s > dataset->ground_truth.back().stamp_s) {
        continue;
      }
      const core::SE2 T_map_base = truth(scan.stamp_s);
      const double dt_s =
          std::abs(scan.angle_increment_rad) / (lidar.rate_hz * 2 * std::numbers::pi);
      const std::vector<lidar::RangePoint> points = lidar::RangePointsAt(
          scan.ranges_m, scan.angle_min_rad, scan.angle_increment_rad, scan.stamp_s, dt_s,
          lidar.T_base_lidar, T_map_base, truth, std::max(options.min_range_m, scan.range_min_m),
          std::min(options.max_range_m, scan.range_max_m));
      const core::Vector2 p_lidar = lidar.T_base_lidar.translation();
      for (const lidar::WallLine& wall : lidar::ExtractWallLines(points, options)) {
        const perception::HesseLine& z = wall.fit.line;
        // The true faces parallel to it within 15 cm that share its extent.
        const Face* best = nullptr;
        double best_error = 0.1, min_true = 1e9, max_true = -1e9;
        for (const Face& f : faces) {
          const core::Vector2 a = T_map_base.Inverse() * f.a_m, b = T_map_base.Inverse() * f.b_m;
          const core::Vector2 d = (b - a).normalized();
          if (std::abs(d.dot(z.Normal())) > std::sin(std::numbers::pi / 180)) continue;
          const double s0 = d.dot(wall.endpoint_a_m - a), s1 = d.dot(wall.endpoint_b_m - a);
          if (std::max(s0, s1) < 0.0 || std::min(s0, s1) > (b - a).norm()) continue;
          const core::Vector2 n(-d.y(), d.x());
          const double true_m = std::abs(n.dot(a - p_lidar));
          const double error_m = std::abs(z.rho_m - z.Normal().dot(p_lidar)) - true_m;
          if (std::abs(error_m) > 0.15) continue;
          min_true = std::min(min_true, true_m);
          max_true = std::max(max_true, true_m);
          if (std::abs(error_m) < std::abs(best_error)) {
            best = &f;
            best_error = error_m;
          }
        }
        if (best == nullptr) continue;
        // A band over faces at several offsets (a dock wall and its recessed
        // doors) has no single true offset.
        Stats& stats = max_true - min_true > 0.01 ? mixed : best->rack ? rack : plain;
        stats.Add(best_error, wall.covariance(0, 0));
        (wall.recessed ? recessed : unimodal).Add(best_error, wall.covariance(0, 0));
      }
    }
  }
  Report(state, "plain", plain);
  Report(state, "rack", rack);
  Report(state, "mixed", mixed);
  Report(state, "recessed", recessed);
  Report(state, "unimodal", unimodal);
}

BENCHMARK_CAPTURE(BM_WallRhoBias, A, "A")->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_WallRhoBias, B, "B")->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_WallRhoBias, C, "C")->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_WallRhoBias, D, "D")->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace
}  // namespace groundline::localization
