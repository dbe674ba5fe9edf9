#include "groundline/localization/lidar/wall_lines.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <random>
#include <vector>

#include "groundline/localization/atlas_walls.h"
#include "groundline/localization/floor_association.h"
#include "groundline/localization/lidar/scan_points.h"
#include "jacobian_check.h"
#include "tools_under_test.h"

namespace groundline::localization::lidar {
namespace {

using Vector12 = Eigen::Matrix<double, 12, 1>;

std::vector<Eigen::Vector2d> Unpack(const Vector12& x) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < 6; ++i) points.emplace_back(x(2 * i), x(2 * i + 1));
  return points;
}

TEST(WallLineFit, WeightedTlsJacobianMatchesNumeric) {
  Vector12 x;  // a noisy face at y ~ 1.1, x from 1 to 6
  x << 1.0, 1.11, 2.0, 1.09, 3.0, 1.12, 4.0, 1.10, 5.0, 1.085, 6.0, 1.115;
  const std::vector<double> weights = {1.0, 2.0, 0.5, 3.0, 1.5, 0.8};
  const auto fit = [&weights](const Vector12& v) {
    const std::vector<Eigen::Vector2d> p = Unpack(v);
    const perception::HesseLine line = perception::FitLineTls(p, weights, 1.0)->line;
    return Eigen::Vector2d(line.rho_m, line.alpha_rad);
  };
  const std::vector<Eigen::Vector2d> p = Unpack(x);
  const perception::HesseLine line = perception::FitLineTls(p, weights, 1.0)->line;
  const Eigen::MatrixXd J = WeightedTlsJacobian(line, p, weights);
  EXPECT_JACOBIAN_NEAR(J, fit, x, 1e-6);
}

// Rays from a sensor at the origin onto the face y = face_y_m between x = 1 and 8 m.
std::vector<RangePoint> RaysOntoFace(double face_y_m, double sigma_m, std::mt19937* rng) {
  std::normal_distribution<double> noise(0.0, sigma_m);
  std::vector<RangePoint> points;
  const double a0 = std::atan2(face_y_m, 8.0), a1 = std::atan2(face_y_m, 1.0);
  for (double a = a0; a <= a1; a += 0.0058) {
    const Eigen::Vector2d u(std::cos(a), std::sin(a));
    const double r = face_y_m / u.y() + noise(*rng);
    points.push_back({r * u, u});
  }
  return points;
}

TEST(WallLineFit, CovarianceMatchesMonteCarlo) {
  if (::groundline::testing::Sanitized()) {
    // CI time: 800 fits take ~22 s under ASan (Debug), 0.1 s in release.
    GTEST_SKIP() << "too slow under AddressSanitizer (Debug); runs in the release build";
  }
  std::mt19937 rng(7);
  const double sigma = 0.015;
  const WallLineFit nominal = *FitWallLine(RaysOntoFace(1.2, sigma, &rng), sigma, 0.0);
  const int trials = 800;
  std::vector<Eigen::Vector2d> samples;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (int t = 0; t < trials; ++t) {
    const WallLineFit fit = *FitWallLine(RaysOntoFace(1.2, sigma, &rng), sigma, 0.0);
    samples.emplace_back(fit.line.rho_m, fit.line.alpha_rad);
    mean += samples.back() / trials;
  }
  Eigen::Matrix2d empirical = Eigen::Matrix2d::Zero();
  for (const Eigen::Vector2d& s : samples) empirical += (s - mean) * (s - mean).transpose();
  empirical /= trials - 1;
  // Unbiased: the true face is rho = 1.2, alpha = pi/2.
  EXPECT_NEAR(mean(0), 1.2, 4.0 * std::sqrt(empirical(0, 0) / trials));
  EXPECT_NEAR(mean(1), M_PI / 2, 4.0 * std::sqrt(empirical(1, 1) / trials));
  // Sample variances within 3 standard errors (sqrt(2 / n) = 5 %).
  EXPECT_NEAR(empirical(0, 0) / nominal.covariance(0, 0), 1.0, 0.15);
  EXPECT_NEAR(empirical(1, 1) / nominal.covariance(1, 1), 1.0, 0.15);
  const double rho_nominal =
      nominal.covariance(0, 1) / std::sqrt(nominal.covariance(0, 0) * nominal.covariance(1, 1));
  const double rho_empirical = empirical(0, 1) / std::sqrt(empirical(0, 0) * empirical(1, 1));
  EXPECT_NEAR(rho_empirical, rho_nominal, 0.1);
  // Grazing rays measure the face far better than the range noise.
  EXPECT_LT(std::sqrt(nominal.covariance(0, 0)), 0.2 * sigma);
}

// Range along the unit ray u from the origin to the axis-aligned box [lo, hi]
// (slab method), or +infinity.
double RayBox(const Eigen::Vector2d& u, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 2; ++k) {
    if (std::abs(u(k)) < 1e-12) {
      if (0.0 < lo(k) || 0.0 > hi(k)) return t1;
      continue;
    }
    const double a = lo(k) / u(k), b = hi(k) / u(k);
    t0 = std::max(t0, std::min(a, b));
    t1 = std::min(t1, std::max(a, b));
  }
  return t0 <= t1 ? t0 : std::numeric_limits<double>::infinity();
}

// Zone B seen from the aisle: a rack face at y = +1.125 (uprights 0.10 m
// wide, 0.08 m deep every 2.7 m; two 1 m loads per bay set back 5 cm), a
// plain wall at y = -1.125, and a pedestrian in the aisle.
std::vector<RangePoint> AisleScan(std::mt19937* rng) {
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> boxes;
  for (int k = -2; k <= 6; ++k) {
    const double x = k * 2.7 - 0.3;
    boxes.push_back({{x, 1.125}, {x + 0.1, 1.205}});
    for (double load : {0.3, 1.5}) boxes.push_back({{x + load, 1.175}, {x + load + 1.0, 2.175}});
  }
  boxes.push_back({{-20.0, -1.4}, {20.0, -1.125}});
  std::normal_distribution<double> noise(0.0, 0.015);
  std::vector<RangePoint> points;
  for (double a = -2.35; a <= 2.35; a += 0.00576) {
    const Eigen::Vector2d u(std::cos(a), std::sin(a));
    double r = std::numeric_limits<double>::infinity();
    for (const auto& [lo, hi] : boxes) r = std::min(r, RayBox(u, lo, hi));
    const Eigen::Vector2d c(3.0, 0.5);  // the pedestrian: a 0.3 m disc
    const double b = u.dot(c);
    const double disc = b * b - (c.squaredNorm() - 0.15 * 0.15);
    if (disc > 0.0 && b > 0.0) r = std::min(r, b - std::sqrt(disc));
    if (r > 12.0) continue;
    r += noise(*rng);
    points.push_back({r * u, u});
  }
  return points;
}

TEST(ExtractWallLines, FindsTheUprightFaceNotTheLoadsAndThePlainWall) {
  std::mt19937 rng(3);
  const std::vector<WallLine> walls = ExtractWallLines(AisleScan(&rng), WallLineOptions());
  ASSERT_GE(walls.size(), 2u);
  int rack = 0, wall = 0;
  for (const WallLine& w : walls) {
    const perception::HesseLine& l = w.fit.line;
    EXPECT_NEAR(std::abs(std::cos(l.alpha_rad)), 0.0, 2e-3);
    if (l.alpha_rad > 0.0) {
      ++rack;
      // The upright fronts (1.125), not the loads (1.175).
      EXPECT_TRUE(w.recessed);
      EXPECT_NEAR(l.rho_m, 1.125, 0.01);
    } else {
      ++wall;
      EXPECT_FALSE(w.recessed);
      EXPECT_NEAR(l.rho_m, 1.125, 0.01);
    }
    EXPECT_GE((w.endpoint_b_m - w.endpoint_a_m).norm(), 3.0);
    EXPECT_GT(w.covariance(0, 0), 0.0);
  }
  EXPECT_EQ(rack, 1);
  EXPECT_EQ(wall, 1);
}

// The offset of both kinds of face is unbiased (wall_lines.h, step 4): the
// mean error over 30 scans (fixed seeds) is within 3 mm (rack -2.5 mm, wall
// +0.0 mm), where the one-sided front search alone put the plain wall
// ~1.5 cm in front of itself.
TEST(ExtractWallLines, RackFaceAndPlainWallOffsetsAreUnbiased) {
  const int scans = 30;
  double rack_sum = 0.0, wall_sum = 0.0, wall_sum2 = 0.0;
  int rack = 0, wall = 0;
  for (int seed = 100; seed < 100 + scans; ++seed) {
    std::mt19937 rng(seed);
    for (const WallLine& w : ExtractWallLines(AisleScan(&rng), WallLineOptions())) {
      const double error_m = w.fit.line.rho_m - 1.125;
      if (std::abs(error_m) > 0.05) continue;  // the loads' sides, when a band holds them
      if (w.fit.line.alpha_rad > 0.0) {
        EXPECT_TRUE(w.recessed);
        rack_sum += error_m;
        ++rack;
      } else {
        EXPECT_FALSE(w.recessed);
        wall_sum += error_m;
        wall_sum2 += error_m * error_m;
        ++wall;
      }
    }
  }
  // A rack band is dropped when its front misses two uprights' span
  // (min_face_span_m) or runs off the band's direction (front_tilt_sigma,
  // which trades a third of these rack faces for the dock walls' mixed bands).
  ASSERT_GE(rack, 20);
  ASSERT_EQ(wall, scans);
  EXPECT_NEAR(rack_sum / rack, 0.0, 0.003);
  EXPECT_NEAR(wall_sum / wall, 0.0, 0.003);
  // And the plain wall's scatter is within its reported rho sigma, floor aside.
  EXPECT_LT(std::sqrt(wall_sum2 / wall), 0.005);
}

TEST(ExtractWallLines, NothingFromScatteredClutter) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(-2.3, 2.3), range(0.5, 8.0);
  std::vector<RangePoint> points;
  for (int i = 0; i < 300; ++i) {
    const double bearing = angle(rng);
    const Eigen::Vector2d u(std::cos(bearing), std::sin(bearing));
    points.push_back({range(rng) * u, u});
  }
  EXPECT_TRUE(ExtractWallLines(points, WallLineOptions()).empty());
}

TEST(WallAtlas, WallObservationsAssociateOnlyWithWalls) {
  Atlas atlas;
  AtlasLine tape;  // a floor tape 2 cm from the rack face, parallel
  tape.id = 0;
  tape.line_map = perception::NormalizeLine(1.105, M_PI / 2);
  tape.covariance = Eigen::Vector2d(1e-4, 1e-4).asDiagonal();
  tape.endpoint_a_m = {-10.0, 1.105};
  tape.endpoint_b_m = {10.0, 1.105};
  atlas.lines.push_back(tape);
  ASSERT_TRUE(AppendWallLines({{{-10.0, 1.125}, {10.0, 1.125}}}, {}, &atlas).ok());
  ASSERT_EQ(atlas.lines.size(), 2u);
  EXPECT_EQ(CountWallLines(atlas), 1);
  EXPECT_EQ(atlas.lines[1].kind, core::MarkingKind::kWall);
  EXPECT_TRUE(atlas.Validate().ok()) << atlas.Validate().message();

  LineObservation z;
  z.line_base = perception::NormalizeLine(1.11, M_PI / 2);  // nearer the tape
  z.covariance = Eigen::Vector2d(1e-4, 1e-4).asDiagonal();
  z.endpoint_a_base_m = {1.0, 1.11};
  z.endpoint_b_base_m = {6.0, 1.11};
  const core::Matrix3 pose_covariance = core::Vector3(1e-4, 1e-4, 1e-5).asDiagonal();
  z.kind = core::MarkingKind::kWall;
  EXPECT_EQ(AssociateLines({z}, atlas, core::SE2(), pose_covariance, {})[0].landmark, 1);
  z.kind = core::MarkingKind::kTapeSolid;
  EXPECT_EQ(AssociateLines({z}, atlas, core::SE2(), pose_covariance, {})[0].landmark, 0);
  // A recessed band (its offset from its front) is a rack face's: against a
  // solid wall it is two faces at different depths, and it is left out.
  z.kind = core::MarkingKind::kRackFace;
  EXPECT_EQ(AssociateLines({z}, atlas, core::SE2(), pose_covariance, {})[0].landmark, -1);
}

TEST(WallAtlas, FaceObservationsMatchOnlyFacesOfTheirKind) {
  // A rack face at y = 1.125 and a solid wall at y = -1.125, both along x.
  Atlas atlas;
  WallSegment rack{{-10.0, 1.125}, {10.0, 1.125}};
  rack.rack_face = true;
  const WallSegment wall{{-10.0, -1.125}, {10.0, -1.125}};
  ASSERT_TRUE(AppendWallLines({rack, wall}, {}, &atlas).ok());
  ASSERT_EQ(atlas.lines.size(), 2u);
  EXPECT_EQ(CountWallLines(atlas), 2);
  EXPECT_EQ(atlas.lines[0].kind, core::MarkingKind::kRackFace);
  EXPECT_EQ(atlas.lines[1].kind, core::MarkingKind::kWall);
  EXPECT_EQ(core::MarkingKindFromName(core::MarkingKindName(core::MarkingKind::kRackFace)),
            core::MarkingKind::kRackFace);

  const core::Matrix3 pose_covariance = core::Vector3(1e-4, 1e-4, 1e-5).asDiagonal();
  const auto associate = [&](double y, core::MarkingKind kind) {
    LineObservation z;
    z.line_base = perception::NormalizeLine(std::abs(y), y > 0 ? M_PI / 2 : -M_PI / 2);
    z.covariance = Eigen::Vector2d(1e-4, 1e-4).asDiagonal();
    z.endpoint_a_base_m = {1.0, y};
    z.endpoint_b_base_m = {6.0, y};
    z.kind = kind;
    return AssociateLines({z}, atlas, core::SE2(), pose_covariance, {})[0].landmark;
  };
  EXPECT_EQ(associate(1.12, core::MarkingKind::kRackFace), 0);
  EXPECT_EQ(associate(1.12, core::MarkingKind::kWall), -1);
  EXPECT_EQ(associate(-1.12, core::MarkingKind::kWall), 1);
  EXPECT_EQ(associate(-1.12, core::MarkingKind::kRackFace), -1);
  EXPECT_EQ(associate(-1.12, core::MarkingKind::kTapeSolid), -1);
}

TEST(RangePointsAt, DeskewsByTheOdometry) {
  // Moving at 1 m/s along x: a ray measured 0.05 s after the reference stamp
  // was cast from 5 cm further along.
  const auto odometry = [](double t) { return core::SE2(t, 0.0, 0.0); };
  const std::vector<double> ranges = {2.0, 2.0};
  const std::vector<RangePoint> points =
      RangePointsAt(ranges, M_PI / 2, 0.0, 0.0, 0.05, core::SE2(0.84, 0.0, 0.0), odometry(0.0),
                    odometry, 0.1, 25.0);
  ASSERT_EQ(points.size(), 2u);
  EXPECT_TRUE(points[0].point_m.isApprox(Eigen::Vector2d(0.84, 2.0), 1e-12));
  EXPECT_TRUE(points[1].point_m.isApprox(Eigen::Vector2d(0.89, 2.0), 1e-12));
  EXPECT_TRUE(points[1].ray_direction.isApprox(Eigen::Vector2d(0.0, 1.0), 1e-12));
}

TEST(ScanPointsFromRanges, EachBeamIsPlacedFromItsOwnLaserPose) {
  // A wall at y = 2 m, the laser at 0.84 m ahead of the base; beam i is
  // measured 5 cm further along x than beam i - 1 and turned 0.01 rad more.
  // Given those poses, every beam lands on the wall at its own x.
  std::vector<double> ranges;
  std::vector<core::SE2> T_base_laser_of_beam;
  const double angle_min = M_PI / 2 - 0.1, increment = 0.02;
  for (int i = 0; i < 11; ++i) {
    const core::SE2 T = core::SE2(0.05 * i, 0.0, 0.01 * i) * core::SE2(0.84, 0.0, 0.0);
    const double a = T.yaw() + angle_min + i * increment;
    ranges.push_back((2.0 - T.y()) / std::sin(a));
    T_base_laser_of_beam.push_back(T);
  }
  ScanPointsOptions options;
  options.voxel_size_m = 0.0;
  const ScanPoints moved = ScanPointsFromRanges(
      ranges, angle_min, increment, 25.0, core::SE2(0.84, 0.0, 0.0), T_base_laser_of_beam, options);
  ASSERT_EQ(moved.points.size(), 11u);
  for (int i = 0; i < 11; ++i) {
    const double a = 0.01 * i + angle_min + i * increment;
    const core::Vector2 expected =
        T_base_laser_of_beam[i].translation() + ranges[i] * core::Vector2(std::cos(a), std::sin(a));
    EXPECT_NEAR(moved.points[i].point_m.y(), 2.0, 1e-12) << i;
    EXPECT_TRUE(moved.points[i].point_m.isApprox(expected, 1e-12)) << i;
    // The wall's normal, from neighbours placed each from its own pose.
    if (moved.points[i].has_normal()) {
      EXPECT_NEAR(std::abs(moved.points[i].normal.y()), 1.0, 1e-9) << i;
    }
  }
  // From one pose (an empty span) the same ranges do not lie on a line.
  const ScanPoints still = ScanPointsFromRanges(ranges, angle_min, increment, 25.0,
                                                core::SE2(0.84, 0.0, 0.0), {}, options);
  ASSERT_EQ(still.points.size(), 11u);
  EXPECT_GT(std::abs(still.points[10].point_m.y() - 2.0), 0.05);
}

}  // namespace
}  // namespace groundline::localization::lidar
