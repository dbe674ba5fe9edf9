// Association of floor observations with the atlas: the chi-square gate at
// its boundary, the pose covariance widening the gate, ambiguity rejection,
// duplicates, and the extent check for collinear markings.
#include "groundline/localization/floor_association.h"

#include <gtest/gtest.h>

#include <cmath>

namespace groundline::localization {
namespace {

constexpr double kSigma = 0.01;

AtlasLine MapLine(std::int64_t id, double rho_m, double alpha_rad, double from_m, double to_m) {
  AtlasLine line;
  line.id = id;
  line.line_map = {rho_m, alpha_rad};
  line.covariance = Eigen::Matrix2d::Identity() * 1e-8;
  line.endpoint_a_m = rho_m * line.line_map.Normal() + from_m * line.line_map.Direction();
  line.endpoint_b_m = rho_m * line.line_map.Normal() + to_m * line.line_map.Direction();
  return line;
}

LineObservation Observed(double rho_m, double alpha_rad) {
  LineObservation observation;
  observation.line_base = {rho_m, alpha_rad};
  observation.covariance = Eigen::Matrix2d::Identity() * kSigma * kSigma;
  const perception::HesseLine& l = observation.line_base;
  observation.endpoint_a_base_m = rho_m * l.Normal() - 0.5 * l.Direction();
  observation.endpoint_b_base_m = rho_m * l.Normal() + 0.5 * l.Direction();
  return observation;
}

TEST(FloorAssociation, GateAcceptsAndRejectsAtTheChiSquareBoundary) {
  Atlas atlas;
  atlas.lines.push_back(MapLine(0, 1.0, 0.0, -5.0, 5.0));
  const double variance = kSigma * kSigma + 1e-8;
  const double boundary_offset = std::sqrt(9.21 * variance);
  const AssociationOptions options;
  const core::Matrix3 no_pose_uncertainty = core::Matrix3::Zero();
  for (const double scale : {0.999, 1.001}) {
    const LineObservation z = Observed(1.0 + scale * boundary_offset, 0.0);
    EXPECT_NEAR(LineMahalanobis2(z, atlas.lines[0], core::SE2(), no_pose_uncertainty),
                9.21 * scale * scale, 1e-9);
    const auto matches = AssociateLines({z}, atlas, core::SE2(), no_pose_uncertainty, options);
    ASSERT_EQ(matches.size(), 1u);
    EXPECT_EQ(matches[0].landmark, scale < 1.0 ? 0 : -1) << scale;
  }
  // A 0.05 m lateral pose uncertainty (along the normal) admits a 10 cm offset.
  core::Matrix3 pose_covariance = core::Matrix3::Zero();
  pose_covariance(0, 0) = 0.05 * 0.05;
  const LineObservation far = Observed(1.1, 0.0);
  EXPECT_EQ(AssociateLines({far}, atlas, core::SE2(), no_pose_uncertainty, options)[0].landmark,
            -1);
  EXPECT_EQ(AssociateLines({far}, atlas, core::SE2(), pose_covariance, options)[0].landmark, 0);
}

TEST(FloorAssociation, TwoLandmarksInsideTheGateAreAmbiguous) {
  Atlas atlas;
  atlas.lines.push_back(MapLine(0, 1.00, 0.0, -5.0, 5.0));
  atlas.lines.push_back(MapLine(1, 1.03, 0.0, -5.0, 5.0));
  const AssociationOptions options;
  const auto between =
      AssociateLines({Observed(1.015, 0.0)}, atlas, core::SE2(), core::Matrix3::Zero(), options);
  EXPECT_EQ(between[0].landmark, -1);
  EXPECT_TRUE(between[0].ambiguous);
  // Right on one of them, the other is > margin further: a clear nearest neighbour.
  const auto on_first =
      AssociateLines({Observed(0.995, 0.0)}, atlas, core::SE2(), core::Matrix3::Zero(), options);
  EXPECT_EQ(on_first[0].landmark, 0);
  EXPECT_FALSE(on_first[0].ambiguous);
}

TEST(FloorAssociation, DuplicatesAreNotAmbiguous) {
  Atlas atlas;
  atlas.lines.push_back(MapLine(0, 1.000, 0.0, -5.0, 5.0));
  atlas.lines.push_back(MapLine(1, 1.001, 0.0, -5.0, 5.0));
  const auto matches = AssociateLines({Observed(1.0005, 0.0)}, atlas, core::SE2(),
                                      core::Matrix3::Zero(), AssociationOptions());
  EXPECT_GE(matches[0].landmark, 0);
}

TEST(FloorAssociation, ExcludedLandmarksAreNoCandidates) {
  Atlas atlas;
  atlas.lines.push_back(MapLine(0, 1.00, 0.0, -5.0, 5.0));
  atlas.lines.push_back(MapLine(1, 1.02, 0.0, -5.0, 5.0));
  atlas.junctions.push_back(
      {0, Eigen::Vector2d(1.0, 0.0), Eigen::Matrix2d::Identity() * 1e-8, std::nullopt});
  const AssociationOptions options;
  const core::Matrix3 exact = core::Matrix3::Zero();
  // Between the two: ambiguous, unless one of them is excluded.
  const std::vector<bool> first_excluded = {true, false};
  const Match between =
      AssociateLines({Observed(1.01, 0.0)}, atlas, core::SE2(), exact, options, &first_excluded)[0];
  EXPECT_EQ(between.landmark, 1);
  EXPECT_FALSE(between.ambiguous);
  // Near the excluded one: the other is outside the gate.
  EXPECT_EQ(AssociateLines({Observed(0.98, 0.0)}, atlas, core::SE2(), exact, options)[0].landmark,
            0);
  EXPECT_EQ(
      AssociateLines({Observed(0.98, 0.0)}, atlas, core::SE2(), exact, options, &first_excluded)[0]
          .landmark,
      -1);
  JunctionObservation on_it;
  on_it.point_base_m = Eigen::Vector2d(1.0, 0.0);
  on_it.covariance = Eigen::Matrix2d::Identity() * kSigma * kSigma;
  const std::vector<bool> none = {false}, all = {true};
  EXPECT_EQ(AssociateJunctions({on_it}, atlas, core::SE2(), exact, options, &none)[0].landmark, 0);
  EXPECT_EQ(AssociateJunctions({on_it}, atlas, core::SE2(), exact, options, &all)[0].landmark, -1);
}

TEST(FloorAssociation, CollinearMarkingsAreSeparatedByTheirExtent) {
  Atlas atlas;
  atlas.lines.push_back(MapLine(0, 1.0, 0.0, -20.0, -10.0));  // behind, along the line
  atlas.lines.push_back(MapLine(1, 1.0, 0.0, -1.0, 3.0));     // where the vehicle is
  const auto matches = AssociateLines({Observed(1.0, 0.0)}, atlas, core::SE2(),
                                      core::Matrix3::Zero(), AssociationOptions());
  EXPECT_EQ(matches[0].landmark, 1);
}

TEST(FloorAssociation, JunctionGate) {
  Atlas atlas;
  atlas.junctions.push_back(
      {0, Eigen::Vector2d(2.0, 1.0), Eigen::Matrix2d::Identity() * 1e-8, std::nullopt});
  const core::SE2 T_map_base(1.0, 1.0, 0.0);
  JunctionObservation near;
  near.point_base_m = Eigen::Vector2d(1.02, 0.0);
  near.covariance = Eigen::Matrix2d::Identity() * kSigma * kSigma;
  JunctionObservation far = near;
  far.point_base_m = Eigen::Vector2d(1.04, 0.0);  // 4 sigma: d2 = 16 > 9.21
  const auto matches = AssociateJunctions({near, far}, atlas, T_map_base, core::Matrix3::Zero(),
                                          AssociationOptions());
  EXPECT_EQ(matches[0].landmark, 0);
  EXPECT_EQ(matches[1].landmark, -1);
}

}  // namespace
}  // namespace groundline::localization
