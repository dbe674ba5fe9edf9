#include "groundline/core/aisle_exits.h"

#include <gtest/gtest.h>

#include <cmath>

namespace groundline::core {
namespace {

FloorMarking Tape(std::int64_t id, Vector2 a, Vector2 b,
                  MarkingKind kind = MarkingKind::kTapeSolid) {
  FloorMarking m;
  m.id = id;
  m.kind = kind;
  m.width_m = 0.05;
  m.polyline_m = {a, b};
  return m;
}

// One aisle between tapes at x = 0 and x = 2.1 from y = 0 to 50 (centre x =
// 1.05), a cross-aisle boundary line along y = -2 and a joint that are no aisle.
FloorMap OneAisle() {
  FloorMap map;
  map.markings = {Tape(1, {0.0, 0.0}, {0.0, 50.0}), Tape(2, {2.1, 0.0}, {2.1, 50.0}),
                  Tape(3, {-10.0, -2.0}, {60.0, -2.0}),
                  Tape(4, {-10.0, 30.0}, {60.0, 30.0}, MarkingKind::kJoint)};
  return map;
}

// 10 Hz samples along a polyline at 1 m/s, heading along each leg.
Trajectory Drive(const std::vector<Vector2>& corners) {
  Trajectory t;
  double stamp_s = 0.0;
  for (std::size_t k = 0; k + 1 < corners.size(); ++k) {
    const Vector2 d = corners[k + 1] - corners[k];
    const int steps = static_cast<int>(std::round(d.norm() / 0.1));
    for (int i = 0; i < steps; ++i) {
      const Vector2 p = corners[k] + d * (static_cast<double>(i) / steps);
      t.push_back({stamp_s, SE2(p.x(), p.y(), std::atan2(d.y(), d.x())), std::nullopt});
      stamp_s += 0.1;
    }
  }
  return t;
}

TEST(AisleExitsTest, FindsTheAisleBetweenTwoParallelTapesOnly) {
  const std::vector<Aisle> aisles = FindAisles(OneAisle(), AisleExitOptions());
  ASSERT_EQ(aisles.size(), 1u);
  EXPECT_NEAR(aisles[0].half_width_m, 1.05, 1e-12);
  EXPECT_NEAR(aisles[0].start_m.x(), 1.05, 1e-12);
  EXPECT_NEAR((aisles[0].end_m - aisles[0].start_m).norm(), 50.0, 1e-12);
  EXPECT_TRUE(aisles[0].Contains({1.0, 25.0}));
  EXPECT_FALSE(aisles[0].Contains({2.2, 25.0}));
  EXPECT_FALSE(aisles[0].Contains({1.0, 50.1}));
}

TEST(AisleExitsTest, AWiderPairSpanningAnAisleIsNotAnAisle) {
  FloorMap map = OneAisle();
  map.markings.push_back(Tape(5, {3.0, 0.0}, {3.0, 50.0}));  // 3.0 m from x = 0, 0.9 m from 2.1
  EXPECT_EQ(FindAisles(map, AisleExitOptions()).size(), 1u);
  map.markings.push_back(Tape(6, {5.5, 0.0}, {5.5, 50.0}));  // 2.5 m from x = 3.0: a second one
  EXPECT_EQ(FindAisles(map, AisleExitOptions()).size(), 2u);
}

TEST(AisleExitsTest, ExitAfterDrivingThroughButNotAfterCrossing) {
  const std::vector<Aisle> aisles = FindAisles(OneAisle(), AisleExitOptions());
  // Up the aisle (y -5 -> 55), then across the aisle's far end region, then
  // straight across the middle of the aisle (2.1 m inside: no exit).
  const Trajectory through = Drive({{1.05, -5.0}, {1.05, 55.0}, {-5.0, 55.0}});
  const std::vector<AisleExit> exits = FindAisleExits(through, aisles, AisleExitOptions());
  ASSERT_EQ(exits.size(), 1u);
  EXPECT_NEAR(exits[0].stamp_s, 55.1, 1e-9);  // first sample beyond y = 50 (y = 50.1)
  const Trajectory across = Drive({{-5.0, 25.0}, {10.0, 25.0}});
  EXPECT_TRUE(FindAisleExits(across, aisles, AisleExitOptions()).empty());
  // Back down the aisle: the exit at the near end.
  const Trajectory back = Drive({{1.05, 55.0}, {1.05, -5.0}});
  const std::vector<AisleExit> down = FindAisleExits(back, aisles, AisleExitOptions());
  ASSERT_EQ(down.size(), 1u);
  EXPECT_NEAR(back[static_cast<std::size_t>(std::round(down[0].stamp_s / 0.1))].pose.y(), -0.1,
              1e-9);
}

TEST(AisleExitsTest, ErrorAtTheExitIsThePositionErrorThere) {
  const Trajectory reference = Drive({{1.05, -5.0}, {1.05, 55.0}, {-5.0, 55.0}});
  // The estimate at 5 Hz, 3 cm ahead along the aisle and 4 cm to the side: 5 cm.
  Trajectory estimate;
  for (std::size_t i = 0; i < reference.size(); i += 2) {
    StampedPose p = reference[i];
    p.pose = SE2(p.pose.x() + 0.04, p.pose.y() + 0.03, p.pose.yaw());
    estimate.push_back(p);
  }
  AisleExitOptions options;
  options.error_threshold_m = 0.049;
  Result<AisleExitSummary> s = ComputeAisleExitErrors(estimate, reference, OneAisle(), options);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(s->n_exits, 1u);
  EXPECT_EQ(s->n_unmatched, 0u);
  EXPECT_NEAR(s->error_m.max, 0.05, 1e-6);
  EXPECT_EQ(s->n_above_threshold, 1u);
  // An estimate that ends before the exit leaves it unmatched.
  estimate.resize(100);
  s = ComputeAisleExitErrors(estimate, reference, OneAisle(), options);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(s->n_unmatched, 1u);
  EXPECT_EQ(s->error_m.n, 0u);
}

TEST(AisleExitsTest, RejectsInvalidOptions) {
  AisleExitOptions options;
  options.max_width_m = 0.5;
  EXPECT_FALSE(options.Validate().ok());
  const Trajectory t = Drive({{0.0, 0.0}, {1.0, 0.0}});
  EXPECT_FALSE(ComputeAisleExitErrors(t, t, OneAisle(), options).ok());
}

}  // namespace
}  // namespace groundline::core
