// A hand-built planar world of wall segments for the LiDAR tests: exact ray
// casting, so the tests know the truth to machine precision.
#ifndef GROUNDLINE_TESTS_LOCALIZATION_LIDAR_TEST_WORLD_H_
#define GROUNDLINE_TESTS_LOCALIZATION_LIDAR_TEST_WORLD_H_

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/localization/lidar/probability_grid.h"
#include "groundline/localization/lidar/scan_points.h"

namespace groundline::testing {

struct Segment {
  core::Vector2 a, b;
};

// Walls of an axis-aligned rectangle [x0, x1] x [y0, y1].
inline void AddBox(std::vector<Segment>* walls, double x0, double y0, double x1, double y1) {
  walls->push_back({{x0, y0}, {x1, y0}});
  walls->push_back({{x1, y0}, {x1, y1}});
  walls->push_back({{x1, y1}, {x0, y1}});
  walls->push_back({{x0, y1}, {x0, y0}});
}

// A 10 m x 8 m room with two pillars and a shelf: constrains every direction.
inline std::vector<Segment> RoomWorld() {
  std::vector<Segment> walls;
  AddBox(&walls, -5.0, -4.0, 5.0, 4.0);
  AddBox(&walls, 1.5, 1.0, 2.0, 1.5);
  AddBox(&walls, -3.0, -2.5, -2.2, -2.0);
  walls.push_back({{-4.0, 2.5}, {-1.0, 3.2}});
  return walls;
}

// A 3 m wide corridor along x, 60 m long: nothing constrains x.
inline std::vector<Segment> CorridorWorld() {
  return {{{-30.0, -1.5}, {30.0, -1.5}}, {{-30.0, 1.5}, {30.0, 1.5}}};
}

// Range along a ray from origin in direction dir (unit) to the nearest wall.
inline double CastRay(const std::vector<Segment>& walls, const core::Vector2& origin,
                      const core::Vector2& dir) {
  double best = std::numeric_limits<double>::infinity();
  for (const Segment& s : walls) {
    const core::Vector2 e = s.b - s.a;
    const double denom = dir.x() * (-e.y()) - dir.y() * (-e.x());
    if (std::abs(denom) < 1e-12) continue;
    const core::Vector2 w = s.a - origin;
    const double t = (w.x() * (-e.y()) - w.y() * (-e.x())) / denom;
    const double u = (dir.x() * w.y() - dir.y() * w.x()) / denom;
    if (t > 0.0 && u >= 0.0 && u <= 1.0) best = std::min(best, t);
  }
  return best;
}

inline constexpr double kPitchM = 2.7;

// A 2.2 m wide aisle along x over [x0, x1]: uprights (0.1 m x 0.08 m) every
// kPitchM on both faces (y = +-1.1) and two 1.0 m pallet loads per bay set
// back 5 cm, a wall behind each rack.
inline std::vector<Segment> AisleWorld(double x0, double x1) {
  std::vector<Segment> walls;
  for (double x = x0; x + kPitchM <= x1 + 1e-9; x += kPitchM) {
    for (double side : {-1.0, 1.0}) {
      const double face = 1.1 * side, depth = 1.1 * side;
      AddBox(&walls, x, std::min(face, face + 0.08 * side), x + 0.1,
             std::max(face, face + 0.08 * side));
      for (double offset : {0.25, 1.45}) {
        const double y0 = face + 0.05 * side, y1 = face + depth;
        AddBox(&walls, x + offset, std::min(y0, y1), x + offset + 1.0, std::max(y0, y1));
      }
    }
  }
  walls.push_back({{x0, -2.4}, {x1, -2.4}});
  walls.push_back({{x0, 2.4}, {x1, 2.4}});
  return walls;
}

// A 360-degree scan at 0.5 deg from the base pose (laser at the base), range
// noise sigma_m with a fixed seed; no-return beams get max_range_m.
inline localization::lidar::ScanPoints SimulateScan(const std::vector<Segment>& walls,
                                                    const core::SE2& T_world_base,
                                                    double sigma_m = 0.0, unsigned seed = 1,
                                                    double max_range_m = 30.0) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma_m > 0.0 ? sigma_m : 1.0);
  const double increment = 0.5 * std::numbers::pi / 180.0;
  const double angle_min = -std::numbers::pi;
  std::vector<double> ranges;
  for (int i = 0; i < 720; ++i) {
    const double a = T_world_base.yaw() + angle_min + i * increment;
    double r = CastRay(walls, T_world_base.translation(), {std::cos(a), std::sin(a)});
    if (sigma_m > 0.0) r += noise(rng);
    ranges.push_back(std::isfinite(r) && r < max_range_m ? r : max_range_m);
  }
  return localization::lidar::ScanPointsFromRanges(ranges, angle_min, increment, max_range_m,
                                                   core::SE2(), {});
}

inline std::vector<core::Vector2> Positions(const localization::lidar::ScanPoints& scan) {
  std::vector<core::Vector2> out;
  for (const localization::lidar::ScanPoint& p : scan.points) out.push_back(p.point_m);
  return out;
}

// A map of the walls from noisy scans at `poses`, each inserted ten times
// (world frame = grid frame).
inline localization::lidar::ProbabilityGrid MapFromScans(const std::vector<Segment>& walls,
                                                         const std::vector<core::SE2>& poses,
                                                         const core::Vector2& origin_m) {
  localization::lidar::ProbabilityGrid grid({}, origin_m);
  for (unsigned k = 0; k < poses.size(); ++k) {
    const localization::lidar::ScanPoints scan = SimulateScan(walls, poses[k], 0.005, 10 + k);
    std::vector<core::Vector2> hits;
    for (const auto& p : scan.points) hits.push_back(poses[k] * p.point_m);
    for (int repeat = 0; repeat < 10; ++repeat) grid.InsertScan(poses[k].translation(), hits);
  }
  return grid;
}

// The room mapped from three poses near the origin.
inline localization::lidar::ProbabilityGrid RoomMap(const std::vector<Segment>& walls) {
  return MapFromScans(walls, {{0.0, 0.0, 0.0}, {-1.0, 0.5, 0.3}, {1.0, -1.0, -0.5}},
                      core::Vector2(-1.0, -1.0));
}

}  // namespace groundline::testing

#endif  // GROUNDLINE_TESTS_LOCALIZATION_LIDAR_TEST_WORLD_H_
