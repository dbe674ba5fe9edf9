// The simulated survey errors of a site's floor map (SurveyedFloorMap) and
// the atlas covariance the localizer derives from the map's survey block:
// the two must agree, or the localizer trusts a surveyed map more or less
// than it deserves.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <numbers>
#include <vector>

#include "groundline/core/floor_map.h"
#include "groundline/localization/atlas.h"
#include "groundline/perception/hesse_line.h"
#include "groundline/sim/sim_run.h"

namespace groundline::sim {
namespace {

using core::FloorMap;
using core::FloorMarking;
using core::MarkingKind;
using core::Vector2;

FloorMarking Marking(std::int64_t id, MarkingKind kind, std::vector<Vector2> polyline) {
  FloorMarking m;
  m.id = id;
  m.kind = kind;
  m.width_m = 0.05;
  m.colour_rgb = {255, 210, 0};
  m.polyline_m = std::move(polyline);
  return m;
}

// A long aisle tape, a short stop bar, a closed staging box far from the
// origin, and a rack face 40 m long.
FloorMap Site() {
  FloorMap map;
  map.markings = {
      Marking(0, MarkingKind::kTapeSolid, {Vector2(0.0, 1.2), Vector2(40.0, 1.2)}),
      Marking(1, MarkingKind::kStopBar, {Vector2(10.0, -0.6), Vector2(10.0, 0.6)}),
      Marking(
          2, MarkingKind::kStagingBoxEdge,
          {Vector2(60, 50), Vector2(63, 50), Vector2(63, 52), Vector2(60, 52), Vector2(60, 50)}),
      Marking(3, MarkingKind::kRackFace, {Vector2(0.0, 2.5), Vector2(40.0, 2.5)}),
  };
  return map;
}

TEST(SurveyNoise, OffLeavesTheExactMapAndOnStatesItsSigmas) {
  const FloorMap exact = Site();
  const FloorMap same = SurveyedFloorMap(exact, SurveyNoiseOptions(), 3);
  EXPECT_FALSE(same.survey.has_value());
  for (std::size_t i = 0; i < exact.markings.size(); ++i) {
    EXPECT_EQ(same.markings[i].polyline_m, exact.markings[i].polyline_m);
  }
  const SurveyNoiseOptions typical = SurveyNoiseOptions::Typical();
  const FloorMap surveyed = SurveyedFloorMap(exact, typical, 3);
  ASSERT_TRUE(surveyed.survey.has_value());
  EXPECT_EQ(surveyed.survey->marking_vertex_sigma_m, 0.003);
  EXPECT_EQ(surveyed.survey->face_offset_sigma_m, 0.02);
  EXPECT_NEAR(surveyed.survey->face_angle_sigma_rad, 0.2 * std::numbers::pi / 180.0, 1e-15);
  EXPECT_TRUE(surveyed.Validate().ok()) << surveyed.Validate().message();
  // Ids, kinds and vertex counts are the exact map's; the outline stays closed.
  for (std::size_t i = 0; i < exact.markings.size(); ++i) {
    EXPECT_EQ(surveyed.markings[i].id, exact.markings[i].id);
    EXPECT_EQ(surveyed.markings[i].kind, exact.markings[i].kind);
    ASSERT_EQ(surveyed.markings[i].polyline_m.size(), exact.markings[i].polyline_m.size());
    EXPECT_NE(surveyed.markings[i].polyline_m.front(), exact.markings[i].polyline_m.front());
  }
  EXPECT_EQ(surveyed.markings[2].polyline_m.front(), surveyed.markings[2].polyline_m.back());
  // A face moves as a whole: its length is kept.
  const auto length = [](const FloorMarking& m) {
    return (m.polyline_m.back() - m.polyline_m.front()).norm();
  };
  EXPECT_NEAR(length(surveyed.markings[3]), length(exact.markings[3]), 1e-9);
  // One draw per seed.
  EXPECT_EQ(SurveyedFloorMap(exact, typical, 3).markings[0].polyline_m,
            surveyed.markings[0].polyline_m);
  EXPECT_NE(SurveyedFloorMap(exact, typical, 4).markings[0].polyline_m,
            surveyed.markings[0].polyline_m);
}

TEST(SurveyNoise, OptionsRefuseNegativeAndPartlyStatedSigmas) {
  SurveyNoiseOptions o = SurveyNoiseOptions::Typical();
  EXPECT_TRUE(o.Validate().ok());
  o.face_offset_sigma_m = 0.0;
  ASSERT_FALSE(o.Validate().ok());
  EXPECT_NE(o.Validate().message().find("face_offset_sigma_m"), std::string::npos);
  o = SurveyNoiseOptions();
  o.marking_vertex_sigma_m = -0.001;
  ASSERT_FALSE(o.Validate().ok());
  EXPECT_NE(o.Validate().message().find("marking_vertex_sigma_m"), std::string::npos);
}

// Over many surveys of one site, the atlas lines' errors against the exact
// lines have the covariance the atlas states from the survey block: the
// normalized squared error averages 2 (two dimensions) for a long tape, a
// short bar, an edge of an outline 80 m from the origin and a rack face.
TEST(SurveyNoise, AtlasCovarianceFromTheSurveyBlockMatchesTheSurveysErrors) {
  const FloorMap exact = Site();
  const localization::Atlas truth = localization::AtlasFromFloorMap(exact, {});
  const SurveyNoiseOptions typical = SurveyNoiseOptions::Typical();
  const int n = 3000;
  std::vector<double> nees(truth.lines.size(), 0.0);
  for (int k = 0; k < n; ++k) {
    const localization::Atlas atlas = localization::AtlasFromFloorMap(
        SurveyedFloorMap(exact, typical, 1000 + static_cast<std::uint64_t>(k)), {});
    ASSERT_EQ(atlas.lines.size(), truth.lines.size());
    for (std::size_t i = 0; i < truth.lines.size(); ++i) {
      const Eigen::Vector2d d =
          perception::LineDifference(atlas.lines[i].line_map, truth.lines[i].line_map);
      nees[i] += d.dot(atlas.lines[i].covariance.ldlt().solve(d)) / n;
    }
  }
  // Mean of a chi-square(2) over 3000 draws: sigma 2/sqrt(3000) = 0.037.
  for (std::size_t i = 0; i < truth.lines.size(); ++i) {
    EXPECT_NEAR(nees[i], 2.0, 0.15)
        << "atlas line " << i << " (kind " << core::MarkingKindName(truth.lines[i].kind) << ")";
  }
}

}  // namespace
}  // namespace groundline::sim
