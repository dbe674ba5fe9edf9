#include "groundline/core/trajectory_association.h"
#include "test_units.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace groundline::core {
namespace {

using ::groundline::testing::kPi;

// Poses at stamps t0 + i * dt_s moving with the given body velocity.
Trajectory Constant(std::size_t n, double dt_s, double v_mps, double w_radps,
                    const SE2& start = SE2(), double t0_s = 0.0) {
  Trajectory trajectory;
  SE2 pose = start;
  for (std::size_t i = 0; i < n; ++i) {
    trajectory.push_back({t0_s + static_cast<double>(i) * dt_s, pose, std::nullopt});
    pose = pose * SE2::Exp(Vector3(v_mps * dt_s, 0.0, w_radps * dt_s));
  }
  return trajectory;
}

TEST(TrajectoryAssociation, NearestMatchesWithinToleranceAndCountsTheRest) {
  const Trajectory reference = Constant(11, 0.1, 1.0, 0.0);  // t = 0, 0.1, ..., 1.0
  Trajectory estimate;
  for (double t : {0.004, 0.05, 0.309, 0.5, 1.008, 1.2}) estimate.push_back({t, SE2(), {}});
  const Result<Association> a = AssociateByStamp(estimate, reference);
  ASSERT_TRUE(a.ok()) << a.message();
  ASSERT_EQ(a->pairs.size(), 4u);  // 0.05 is 50 ms from both neighbours, 1.2 past the end
  EXPECT_EQ(a->n_unmatched, 2u);
  EXPECT_NEAR(a->pairs[0].T_map_ref.x(), 0.0, 1e-12);
  EXPECT_NEAR(a->pairs[1].T_map_ref.x(), 0.3, 1e-12);  // nearest to 0.309 is 0.3
  EXPECT_NEAR(a->pairs[2].T_map_ref.x(), 0.5, 1e-12);
  EXPECT_NEAR(a->pairs[3].T_map_ref.x(), 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(a->pairs[1].stamp_s, 0.309);
}

TEST(TrajectoryAssociation, InterpolationFollowsTheReferenceBetweenPoses) {
  const Trajectory reference = {{0.0, SE2(0, 0, 0), {}}, {1.0, SE2(1, 0, 0), {}}};
  const Trajectory estimate = {{0.25, SE2(0.25, 0, 0), {}}};
  AssociationOptions nearest;
  nearest.max_dt_s = 0.5;
  const Result<Association> by_nearest = AssociateByStamp(estimate, reference, nearest);
  ASSERT_TRUE(by_nearest.ok());
  EXPECT_NEAR(by_nearest->pairs[0].T_map_ref.x(), 0.0, 1e-12);

  AssociationOptions interp;
  interp.method = AssociationMethod::kInterpolate;
  const Result<Association> by_interp = AssociateByStamp(estimate, reference, interp);
  ASSERT_TRUE(by_interp.ok());
  EXPECT_TRUE(by_interp->pairs[0].T_map_ref.IsApprox(SE2(0.25, 0, 0), 1e-12, 1e-12));
}

TEST(TrajectoryAssociation, InterpolationIsOnSE2) {
  // A quarter circle of radius 1 as one constant twist: the midpoint lies on the arc.
  const SE2 a(0.0, 0.0, 0.0);
  const SE2 b = SE2::Exp(Vector3(kPi / 2.0, 0.0, kPi / 2.0));
  EXPECT_TRUE(b.IsApprox(SE2(1.0, 1.0, kPi / 2.0), 1e-12, 1e-12));
  const SE2 mid = InterpolateSE2(a, b, 0.5);
  EXPECT_TRUE(mid.IsApprox(SE2(std::sin(kPi / 4), 1.0 - std::cos(kPi / 4), kPi / 4), 1e-12, 1e-12));
  EXPECT_TRUE(InterpolateSE2(a, b, 0.0).IsApprox(a, 1e-12, 1e-12));
  EXPECT_TRUE(InterpolateSE2(a, b, 1.0).IsApprox(b, 1e-12, 1e-12));
  // Across the +-pi cut the short way round.
  const SE2 c(0, 0, kPi - 0.1), d(0, 0, -kPi + 0.1);
  EXPECT_NEAR(std::abs(InterpolateSE2(c, d, 0.5).yaw()), kPi, 1e-12);
}

TEST(TrajectoryAssociation, InterpolationNeitherExtrapolatesNorBridgesLongGaps) {
  const Trajectory reference = {
      {0.0, SE2(0, 0, 0), {}}, {0.5, SE2(0.5, 0, 0), {}}, {3.0, SE2(3, 0, 0), {}}};
  const Trajectory estimate = {{-0.005, SE2(), {}},  // just before the start: takes pose 0
                               {-0.5, SE2(), {}},    // too early
                               {1.0, SE2(), {}},     // inside a 2.5 s gap
                               {3.5, SE2(), {}}};    // after the end
  Trajectory sorted = estimate;
  std::sort(sorted.begin(), sorted.end(),
            [](const StampedPose& x, const StampedPose& y) { return x.stamp_s < y.stamp_s; });
  AssociationOptions options;
  options.method = AssociationMethod::kInterpolate;
  const Result<Association> a = AssociateByStamp(sorted, reference, options);
  ASSERT_TRUE(a.ok()) << a.message();
  ASSERT_EQ(a->pairs.size(), 1u);
  EXPECT_EQ(a->n_unmatched, 3u);
  EXPECT_DOUBLE_EQ(a->pairs[0].stamp_s, -0.005);
  options.max_interpolation_gap_s = 3.0;
  const Result<Association> bridged = AssociateByStamp(sorted, reference, options);
  ASSERT_TRUE(bridged.ok());
  ASSERT_EQ(bridged->pairs.size(), 2u);
  EXPECT_NEAR(bridged->pairs[1].T_map_ref.x(), 1.0, 1e-12);
}

TEST(TrajectoryAssociation, DirectionOfTravelIsThePathTangent) {
  AssociationOptions options;
  // Driving along +y with the heading pointing elsewhere (a crab motion): the path wins.
  Trajectory crab;
  for (int i = 0; i < 20; ++i) crab.push_back({0.1 * i, SE2(0.0, 0.1 * i, 0.3), {}});
  bool from_heading = true;
  Vector2 u = ReferenceDirectionOfTravel(crab, 0.95, options, &from_heading);
  EXPECT_FALSE(from_heading);
  EXPECT_NEAR(u.x(), 0.0, 1e-12);
  EXPECT_NEAR(u.y(), 1.0, 1e-12);
  // Reversing along -x with heading +x: the tangent points backwards.
  const Trajectory reverse = Constant(20, 0.1, -1.0, 0.0);
  u = ReferenceDirectionOfTravel(reverse, 1.0, options);
  EXPECT_NEAR(u.x(), -1.0, 1e-12);
  // On a circle the tangent is perpendicular to the radius (central chord).
  const Trajectory circle = Constant(200, 0.05, 1.0, 0.5);  // radius 2 m
  u = ReferenceDirectionOfTravel(circle, 5.0, options, &from_heading);
  EXPECT_FALSE(from_heading);
  EXPECT_NEAR(u.x(), std::cos(2.5), 1e-9);
  EXPECT_NEAR(u.y(), std::sin(2.5), 1e-9);
}

TEST(TrajectoryAssociation, DirectionFallsBackToHeadingWhenNotTranslating) {
  AssociationOptions options;
  const Trajectory still = Constant(30, 0.1, 0.0, 0.0, SE2(1.0, 2.0, 2.0));
  bool from_heading = false;
  Vector2 u = ReferenceDirectionOfTravel(still, 1.5, options, &from_heading);
  EXPECT_TRUE(from_heading);
  EXPECT_NEAR(u.x(), std::cos(2.0), 1e-12);
  EXPECT_NEAR(u.y(), std::sin(2.0), 1e-12);
  // Turning on the spot: the heading of the nearest pose.
  const Trajectory spin = Constant(30, 0.1, 0.0, 1.0);
  u = ReferenceDirectionOfTravel(spin, 1.0, options, &from_heading);
  EXPECT_TRUE(from_heading);
  EXPECT_NEAR(u.x(), std::cos(1.0), 1e-9);
  EXPECT_NEAR(u.y(), std::sin(1.0), 1e-9);
  // Creeping 1 cm per pose: the chord widens to 5 cm and still gives the path.
  const Trajectory creep = Constant(60, 0.1, 0.1, 0.0, SE2(0, 0, 0.4));
  u = ReferenceDirectionOfTravel(creep, 3.0, options, &from_heading);
  EXPECT_FALSE(from_heading);
  EXPECT_NEAR(std::atan2(u.y(), u.x()), 0.4, 1e-9);
}

TEST(TrajectoryAssociation, BadInputsGiveErrorsNotCrashes) {
  const Trajectory reference = Constant(10, 0.1, 1.0, 0.0);
  EXPECT_FALSE(AssociateByStamp({}, reference).ok());
  EXPECT_FALSE(AssociateByStamp(reference, {}).ok());
  Trajectory unsorted = reference;
  std::swap(unsorted[2], unsorted[3]);
  const Result<Association> bad_order = AssociateByStamp(unsorted, reference);
  ASSERT_FALSE(bad_order.ok());
  EXPECT_NE(bad_order.message().find("estimate"), std::string::npos);
  Trajectory nan = reference;
  nan[4].pose = SE2(std::nan(""), 0.0, 0.0);
  EXPECT_FALSE(AssociateByStamp(reference, nan).ok());
  // Different clocks: nothing matches, and the message shows both spans.
  const Trajectory shifted = Constant(10, 0.1, 1.0, 0.0, SE2(), 1000.0);
  const Result<Association> none = AssociateByStamp(shifted, reference);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.message().find("1000.0"), std::string::npos) << none.message();
  EXPECT_NE(none.message().find("--max-dt-s"), std::string::npos);
  AssociationOptions negative;
  negative.max_dt_s = -1.0;
  EXPECT_FALSE(negative.Validate().ok());
  EXPECT_FALSE(AssociateByStamp(reference, reference, negative).ok());
}

}  // namespace
}  // namespace groundline::core
