// A hand-built planar world of wall segments for the LiDAR tests: exact ray
// casting, so the tests know the truth to machine precision.
#ifndef GROUNDLINE_TESTS_LOCALIZATION_LIDAR_TEST_WORLD_H_
#define GROUNDLINE_TESTS_LOCALIZATION_LIDAR_TEST_WORLD_H_

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

// A map of the walls from noisy scans at three poses near the origin, each
// inserted three times (world frame = grid frame).
inline localization::lidar::ProbabilityGrid RoomMap(const std::vector<Segment>& walls) {
  localization::lidar::ProbabilityGrid grid({}, core::Vector2(-1.0, -1.0));
  const core::SE2 poses[] = {{0.0, 0.0, 0.0}, {-1.0, 0.5, 0.3}, {1.0, -1.0, -0.5}};
  for (unsigned k = 0; k < 3; ++k) {
    const localization::lidar::ScanPoints scan = SimulateScan(walls, poses[k], 0.005, 10 + k);
    std::vector<core::Vector2> hits;
    for (const auto& p : scan.points) hits.push_back(poses[k] * p.point_m);
    for (int repeat = 0; repeat < 10; ++repeat) grid.InsertScan(poses[k].translation(), hits);
  }
  return grid;
}

}  // namespace groundline::testing

#endif  // GROUNDLINE_TESTS_LOCALIZATION_LIDAR_TEST_WORLD_H_
