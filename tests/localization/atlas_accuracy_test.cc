#include "groundline/localization/atlas_accuracy.h"

#include <gtest/gtest.h>

#include <cmath>

namespace groundline::localization {
namespace {

AtlasLine Line(double x0, double y0, double x1, double y1, core::MarkingKind kind, double sigma_m) {
  AtlasLine l;
  l.line_map = *perception::LineFromPoints({x0, y0}, {x1, y1});
  l.endpoint_a_m = {x0, y0};
  l.endpoint_b_m = {x1, y1};
  l.kind = kind;
  l.covariance =
      LineCovarianceAbout(l.line_map, 0.5 * (l.endpoint_a_m + l.endpoint_b_m), sigma_m, 1e-3);
  return l;
}

TEST(CompareAtlases, OffsetsAreMeasuredWhereTheLineWasSeenAndWeighedByItsCovariance) {
  Atlas reference, built;
  // Far from the origin, so that rho about it would mix in the direction error.
  reference.lines = {Line(80, 0, 80, 10, core::MarkingKind::kTapeSolid, 0.0),
                     Line(60, 5, 70, 5, core::MarkingKind::kTapeSolid, 0.0),
                     Line(90, 0, 90, 30, core::MarkingKind::kWall, 0.0),
                     Line(0, 0, 5, 0, core::MarkingKind::kTapeSolid, 0.0)};
  reference.junctions.push_back({1, {80, 0}, Eigen::Matrix2d::Identity(), std::nullopt});
  // 2 mm and 12 mm off (sigma 2 mm: inside and outside 3 sigma), a face 1 cm
  // off, a line of another family at the face's place (never paired with it),
  // a line where the reference has none.
  built.lines = {Line(80.002, 0, 80.002, 10, core::MarkingKind::kTapeSolid, 0.002),
                 Line(60, 5.012, 70, 5.012, core::MarkingKind::kTapeSolid, 0.002),
                 Line(90.01, 0, 90.01, 30, core::MarkingKind::kRackFace, 0.005),
                 Line(90.0, 0, 90.0, 30, core::MarkingKind::kTapeSolid, 0.002),
                 Line(40, 40, 45, 40, core::MarkingKind::kTapeSolid, 0.002)};
  built.junctions.push_back({1, {80.003, 0.004}, Eigen::Matrix2d::Identity() * 1e-4, std::nullopt});
  const AtlasAccuracy a = CompareAtlases(built, reference);
  EXPECT_EQ(a.floor_lines.built, 4);
  EXPECT_EQ(a.floor_lines.paired, 2);
  EXPECT_NEAR(a.floor_lines.median_abs_rho_m, 0.007, 1e-9);  // of 2 and 12 mm
  EXPECT_NEAR(a.floor_lines.max_abs_rho_m, 0.012, 1e-9);
  EXPECT_NEAR(a.floor_lines.median_abs_alpha_rad, 0.0, 1e-9);
  EXPECT_NEAR(a.floor_lines.within_3_sigma, 0.5, 1e-12);
  EXPECT_EQ(a.faces.paired, 1);
  EXPECT_NEAR(a.faces.median_abs_rho_m, 0.01, 1e-9);
  EXPECT_EQ(a.junctions.paired, 1);
  EXPECT_NEAR(a.junctions.median_abs_rho_m, 0.005, 1e-9);
  EXPECT_NEAR(a.junctions.within_3_sigma, 1.0, 1e-12);
}

}  // namespace
}  // namespace groundline::localization
