#include "groundline/localization/atlas_mapper.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "groundline/core/covariance.h"
#include "groundline/core/trajectory_association.h"
#include "lidar_test_world.h"

namespace groundline::localization {
namespace {

// Two laps of a 1.2 m circle in the room of lidar_test_world.h at 0.5 m/s.
constexpr double kRadius = 1.2, kSpeed = 0.5;
constexpr double kDuration = 2.0 * 2.0 * std::numbers::pi * kRadius / kSpeed;

core::SE2 Truth(double t) {
  const double a = kSpeed * t / kRadius;
  return core::SE2(-0.5 + kRadius * std::sin(a), kRadius - kRadius * std::cos(a), a);
}

// Odometry that reads the distance 2 % long and the turn 1 % short: after
// two laps the dead reckoning is decimetres off.
core::SE2 Odometry(double t) {
  const double a = 0.99 * kSpeed * t / kRadius;
  const double r = 1.02 * kRadius / 0.99;
  return core::SE2(-0.5 + r * std::sin(a), r - r * std::cos(a), a);
}

struct FloorSegment {
  Eigen::Vector2d a, b;
};
// Tape on the room's floor: two long lines across the circle, one L.
std::vector<FloorSegment> FloorMarkings() {
  return {{{-3.0, 0.6}, {2.5, 0.6}},
          {{0.3, -1.5}, {0.3, 3.0}},
          {{1.6, 1.4}, {2.6, 1.4}},
          {{1.6, 1.4}, {1.6, 3.0}}};
}

// What the camera (1.5 m ahead, 1 m across) and the LiDAR's face extraction
// (every room wall within 6 m) see from the true pose, with noise.
FloorObservations SeeFloor(const core::SE2& T, std::mt19937* rng,
                           std::vector<LineObservation>* faces) {
  std::normal_distribution<double> n(0.0, 1.0);
  FloorObservations out;
  const auto observe = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b, double sigma_m,
                           double sigma_rad, core::MarkingKind kind) {
    LineObservation o;
    const perception::HesseLine world = *perception::LineFromPoints(a, b);
    const perception::HesseLine base = perception::InverseTransformLine(T, world);
    o.line_base = perception::NormalizeLine(base.rho_m + sigma_m * n(*rng),
                                            base.alpha_rad + sigma_rad * n(*rng));
    o.covariance = Eigen::Vector2d(sigma_m * sigma_m, sigma_rad * sigma_rad).asDiagonal();
    o.kind = kind;
    o.endpoint_a_base_m = T.Inverse() * a;
    o.endpoint_b_base_m = T.Inverse() * b;
    return o;
  };
  const auto in_view = [&](const Eigen::Vector2d& p) {
    const Eigen::Vector2d q = T.Inverse() * p;
    return q.x() > 0.6 && q.x() < 2.1 && std::abs(q.y()) < 1.0;
  };
  for (const FloorSegment& s : FloorMarkings()) {
    // The visible part: the segment clipped to the view, sampled.
    std::vector<Eigen::Vector2d> seen;
    for (int i = 0; i <= 100; ++i) {
      const Eigen::Vector2d p = s.a + (s.b - s.a) * (i / 100.0);
      if (in_view(p)) seen.push_back(p);
    }
    if (seen.size() < 5) continue;
    out.lines.push_back(
        observe(seen.front(), seen.back(), 0.003, 0.003, core::MarkingKind::kTapeSolid));
  }
  if (in_view({1.6, 1.4})) {
    JunctionObservation j;
    j.point_base_m =
        T.Inverse() * Eigen::Vector2d(1.6, 1.4) + Eigen::Vector2d(0.004 * n(*rng), 0.004 * n(*rng));
    j.covariance = Eigen::Matrix2d::Identity() * 0.004 * 0.004;
    out.junctions.push_back(j);
  }
  faces->clear();
  for (const testing::Segment& w : testing::RoomWorld()) {
    if ((w.b - w.a).norm() < 2.0) continue;  // pillars: too short to extract
    faces->push_back(observe(w.a, w.b, 0.005, 0.002, core::MarkingKind::kWall));
  }
  return out;
}

// The drive fed to the mapper (two laps, or the first duration_s of them):
// scans at 15 Hz, keyframes every 0.3 s. T_believed_true: where the
// vehicle's odometry frame is, against the truth (identity: the odometry
// starts at the true start pose).
void DriveTwoLaps(AtlasMapper* mapper, const core::SE2& T_believed_true = core::SE2(),
                  double duration_s = kDuration) {
  std::mt19937 rng(7);
  const std::vector<testing::Segment> walls = testing::RoomWorld();
  double next_keyframe_s = 0.0;
  for (int k = 1; k * (1.0 / 15.0) <= duration_s; ++k) {
    const double t = k / 15.0;
    const core::SE2 odometry = T_believed_true * Odometry(t);
    ASSERT_TRUE(mapper->AddScan(t, odometry, testing::SimulateScan(walls, Truth(t), 0.01, k)).ok());
    if (t >= next_keyframe_s) {
      std::vector<LineObservation> faces;
      const FloorObservations floor = SeeFloor(Truth(t), &rng, &faces);
      mapper->AddKeyframe(t, odometry, floor, faces);
      next_keyframe_s = t + 0.3;
    }
  }
}

// The error of each built floor line against the marking it is nearest to:
// the largest |rho| (at the marking's middle) and |alpha|.
std::pair<double, double> WorstFloorLineError(const Atlas& atlas) {
  double worst_m = 0.0, worst_rad = 0.0;
  for (const AtlasLine& line : atlas.lines) {
    if (core::IsFaceKind(line.kind)) continue;
    double best = 1e9, offset = 0.0, angle = 0.0;
    for (const FloorSegment& m : FloorMarkings()) {
      const Eigen::Vector2d e =
          perception::LineDifference(line.line_map, *perception::LineFromPoints(m.a, m.b));
      const double at_middle = perception::SignedDistance(line.line_map, 0.5 * (m.a + m.b));
      if (std::abs(at_middle) + std::abs(e(1)) < best) {
        best = std::abs(at_middle) + std::abs(e(1)), offset = at_middle, angle = e(1);
      }
    }
    worst_m = std::max(worst_m, std::abs(offset));
    worst_rad = std::max(worst_rad, std::abs(angle));
  }
  return {worst_m, worst_rad};
}

TEST(AtlasMapper, TwoLapsWithDriftingWheelsMapEachMarkingOnceWithinItsCovariance) {
  AtlasMapperOptions options;
  AtlasMapper mapper(options);
  DriveTwoLaps(&mapper);
  AtlasMapperReport report;
  core::Result<Atlas> atlas = mapper.Build(&report);
  ASSERT_TRUE(atlas.ok()) << atlas.message();
  EXPECT_TRUE(report.covariances);
  EXPECT_TRUE(atlas->covariances_stated);  // the marginals are the landmarks' accuracy
  // Every landmark says when it was seen: a wall all along the two laps, a
  // marking over at least the two keyframes that kept it.
  for (const AtlasLine& line : atlas->lines) {
    ASSERT_TRUE(line.seen.has_value()) << "line " << line.id;
    EXPECT_GE(line.seen->keyframes, 2) << "line " << line.id;
    EXPECT_LE(line.seen->first_s, line.seen->last_s);
    if (core::IsFaceKind(line.kind)) {
      EXPECT_GT(line.seen->last_s - line.seen->first_s, 0.5 * kDuration) << "face " << line.id;
    }
  }
  // The wheels alone end decimetres off; the mapped trajectory does not.
  EXPECT_GT((Odometry(kDuration).translation() - Truth(kDuration).translation()).norm(), 0.15);
  double worst_m = 0.0;
  for (const core::StampedPose& p : mapper.keyframe_trajectory()) {
    worst_m = std::max(worst_m, (p.pose.translation() - Truth(p.stamp_s).translation()).norm());
  }
  EXPECT_LT(worst_m, 0.03);

  // Each marking is in the atlas, as one line or as collinear pieces where a
  // part of it was never in view (the long line across the circle), but
  // never twice over the same stretch; each room wall once (the pillars are
  // too short for faces).
  const std::vector<FloorSegment> markings = FloorMarkings();
  EXPECT_EQ(report.faces, 5);
  EXPECT_EQ(report.junctions, 1);
  std::vector<std::vector<std::pair<double, double>>> pieces(markings.size());
  int inside_3_sigma = 0, checked = 0;
  for (const AtlasLine& line : atlas->lines) {
    if (core::IsFaceKind(line.kind)) continue;
    std::size_t marking = 0;
    double best = 1e9;
    Eigen::Vector2d error;
    for (std::size_t m = 0; m < markings.size(); ++m) {
      const Eigen::Vector2d e = perception::LineError(
          line.line_map, *perception::LineFromPoints(markings[m].a, markings[m].b));
      if (std::abs(e(0)) + std::abs(e(1)) < best) {
        best = std::abs(e(0)) + std::abs(e(1)), error = e, marking = m;
      }
    }
    EXPECT_LT(std::abs(error(0)), 0.005) << "line " << line.id;
    EXPECT_LT(std::abs(error(1)), 0.2 * std::numbers::pi / 180.0) << "line " << line.id;
    ++checked;
    inside_3_sigma += core::SquaredMahalanobis<2>(error, line.covariance) <= 11.8;
    const Eigen::Vector2d d = (markings[marking].b - markings[marking].a).normalized();
    const double s_a = d.dot(line.endpoint_a_m - markings[marking].a);
    const double s_b = d.dot(line.endpoint_b_m - markings[marking].a);
    pieces[marking].push_back({std::min(s_a, s_b), std::max(s_a, s_b)});
  }
  for (std::size_t m = 0; m < markings.size(); ++m) {
    EXPECT_FALSE(pieces[m].empty()) << "marking " << m << " is missing";
    std::sort(pieces[m].begin(), pieces[m].end());
    for (std::size_t i = 1; i < pieces[m].size(); ++i) {
      EXPECT_GT(pieces[m][i].first, pieces[m][i - 1].second) << "marking " << m << " twice";
    }
  }
  EXPECT_EQ(inside_3_sigma, checked);
  const double junction_error = (atlas->junctions.at(0).point_m - Eigen::Vector2d(1.6, 1.4)).norm();
  EXPECT_LT(junction_error, 0.01);
}

// A start pose whose heading is 10 mrad off turns the whole atlas of one lap
// about the start; two surveyed markings far apart (1 mm, 0.5 mrad) and a
// surveyed junction (1 mm) turn it back onto the site frame.
TEST(AtlasMapper, SurveyedMarkingsTieTheAtlasToTheSiteWhereTheStartPoseIsTurned) {
  const core::SE2 start = Truth(0.0);
  const core::SE2 believed(start.x(), start.y(), start.yaw() + 0.01);
  const core::Matrix3 start_covariance = core::Vector3(1e-4, 1e-4, 9e-4).asDiagonal();
  Atlas survey;
  for (const int m : {0, 3}) {
    const FloorSegment marking = FloorMarkings()[static_cast<std::size_t>(m)];
    AtlasLine line;
    line.id = m + 1;
    line.kind = core::MarkingKind::kTapeSolid;
    line.line_map = *perception::LineFromPoints(marking.a, marking.b);
    line.covariance = Eigen::Vector2d(1e-6, 0.25e-6).asDiagonal();
    line.endpoint_a_m = marking.a;
    line.endpoint_b_m = marking.b;
    survey.lines.push_back(line);
  }
  // And the corner of the L, where two of them meet.
  survey.junctions.push_back(
      {1, Eigen::Vector2d(1.6, 1.4), Eigen::Matrix2d::Identity() * 1e-6, std::nullopt});
  std::pair<double, double> free_error, surveyed_error;
  for (const bool surveyed : {false, true}) {
    AtlasMapper mapper{AtlasMapperOptions()};
    mapper.SetAnchor(believed, start_covariance);
    if (surveyed) {
      ASSERT_TRUE(mapper.SetSurveyedLandmarks(survey).ok());
    }
    DriveTwoLaps(&mapper, believed * start.Inverse(), 0.5 * kDuration);  // one lap
    AtlasMapperReport report;
    core::Result<Atlas> atlas = mapper.Build(&report);
    ASSERT_TRUE(atlas.ok()) << atlas.message();
    (surveyed ? surveyed_error : free_error) = WorstFloorLineError(*atlas);
    EXPECT_EQ(report.surveyed, surveyed ? 3 : 0);
    EXPECT_EQ(report.surveyed_matched, surveyed ? 3 : 0);
    EXPECT_EQ(report.surveyed_ambiguous, 0);
    if (!surveyed) continue;
    ASSERT_EQ(atlas->junctions.size(), 1u);
    EXPECT_LT((atlas->junctions[0].point_m - Eigen::Vector2d(1.6, 1.4)).norm(), 0.005);
    double worst_m = 0.0;
    for (const core::StampedPose& p : mapper.keyframe_trajectory()) {
      worst_m = std::max(worst_m, (p.pose.translation() - Truth(p.stamp_s).translation()).norm());
    }
    EXPECT_LT(worst_m, 0.03);
  }
  // Free, the lines are turned with the start pose (up to 10 mrad); tied to
  // the survey, within 5 mm and 0.2 deg.
  EXPECT_GT(free_error.second, 0.007);
  EXPECT_LT(surveyed_error.first, 0.005);
  EXPECT_LT(surveyed_error.second, 0.2 * std::numbers::pi / 180.0);
}

TEST(AtlasMapper, RefusesAnInvalidSurvey) {
  AtlasMapper mapper{AtlasMapperOptions()};
  Atlas survey;
  AtlasLine line;
  line.line_map = perception::NormalizeLine(1.0, 0.0);
  line.covariance = -Eigen::Matrix2d::Identity();
  survey.lines.push_back(line);
  EXPECT_FALSE(mapper.SetSurveyedLandmarks(survey).ok());
}

TEST(AtlasMapper, WithoutKeyframesThereIsNoAtlas) {
  AtlasMapper mapper{AtlasMapperOptions()};
  EXPECT_FALSE(mapper.Build().ok());
}

TEST(AtlasMapper, RefusesInvalidOptions) {
  AtlasMapperOptions options;
  options.min_line_sightings = 0;
  EXPECT_FALSE(options.Validate().ok());
  options = AtlasMapperOptions();
  options.pose_sigma_m = 0.0;
  EXPECT_FALSE(options.Validate().ok());
}

}  // namespace
}  // namespace groundline::localization
