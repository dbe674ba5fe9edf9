// False lines counted per nuisance class (line_evaluation.h: NuisanceAlong,
// LineEvaluation::by_nuisance) and the simulator's nuisance truth file
// (nuisance_truth.h).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "groundline/perception/line_evaluation.h"
#include "groundline/perception/nuisance_truth.h"

namespace groundline::perception {
namespace {

ExtractedLine Segment(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  ExtractedLine l;
  l.start_m = a;
  l.end_m = b;
  const Eigen::Vector2d d = (b - a).normalized();
  const Eigen::Vector2d n(-d.y(), d.x());
  l.line = NormalizeLine(n.dot(a), std::atan2(n.y(), n.x()));
  l.covariance = Eigen::Vector2d(1e-6, 1e-6).asDiagonal();
  return l;
}

TEST(NuisanceAttribution, ALineAlongANuisanceIsItsClass) {
  const std::vector<NuisanceLine> nuisances = {
      {"cast_shadow_edge", {1.0, 0.5}, {2.5, 0.5}},
      {"tire_mark", {1.0, -0.3}, {2.5, -0.3}},
  };
  EXPECT_EQ(NuisanceAlong(Segment({1.2, 0.52}, {2.0, 0.51}), nuisances), "cast_shadow_edge");
  EXPECT_EQ(NuisanceAlong(Segment({2.0, -0.28}, {1.1, -0.31}), nuisances), "tire_mark");
  // 8 cm beside, 8 deg across, and beyond the nuisance's end: none.
  EXPECT_EQ(NuisanceAlong(Segment({1.2, 0.58}, {2.0, 0.58}), nuisances), "");
  EXPECT_EQ(NuisanceAlong(Segment({1.2, 0.5}, {2.0, 0.5 + 0.8 * std::tan(0.14)}), nuisances), "");
  EXPECT_EQ(NuisanceAlong(Segment({2.6, 0.5}, {3.2, 0.5}), nuisances), "");
  // Between two parallel nuisances the nearer one wins.
  const std::vector<NuisanceLine> pair = {{"patch_seam", {0, 0.0}, {3, 0.0}},
                                          {"glare_row", {0, 0.06}, {3, 0.06}}};
  EXPECT_EQ(NuisanceAlong(Segment({1, 0.04}, {2, 0.04}), pair), "glare_row");
  EXPECT_EQ(NuisanceAlong(Segment({1, 0.02}, {2, 0.02}), pair), "patch_seam");
}

TEST(NuisanceAttribution, EvaluationCountsFalseLinesAndTouchedTruthsPerClass) {
  TrueLine truth;
  truth.line = NormalizeLine(0.0, M_PI / 2);  // y = 0
  truth.start_m = {1.0, 0.0};
  truth.end_m = {2.0, 0.0};
  truth.evaluated = true;
  const std::vector<TrueLine> truths = {truth};
  // A shadow edge crossing the true line; a tire mark far from it.
  const std::vector<NuisanceLine> nuisances = {{"cast_shadow_edge", {1.5, -1.0}, {1.5, 1.0}},
                                               {"tire_mark", {1.0, 0.8}, {2.5, 0.8}}};
  const std::vector<ExtractedLine> extracted = {
      Segment({1.1, 0.0}, {1.9, 0.0}),    // the true line
      Segment({1.5, -0.6}, {1.5, 0.6}),   // along the shadow edge
      Segment({1.2, 0.81}, {2.2, 0.79}),  // along the tire mark
      Segment({1.2, -0.5}, {2.0, -0.9}),  // along nothing
  };
  LineMatches matches;
  matches.truth_of_extracted = {0, -1, -1, -1};
  matches.extracted_of_truth = {0};
  LineEvaluation evaluation;
  evaluation.AddFrame(extracted, truths, matches, &nuisances);
  const auto& by = evaluation.by_nuisance();
  ASSERT_EQ(by.size(), 3u);
  EXPECT_EQ(by.at("cast_shadow_edge").false_detections, 1);
  EXPECT_EQ(by.at("cast_shadow_edge").evaluated_truths, 1);
  EXPECT_EQ(by.at("cast_shadow_edge").detected_truths, 1);
  EXPECT_EQ(by.at("tire_mark").false_detections, 1);
  EXPECT_EQ(by.at("tire_mark").evaluated_truths, 0);
  EXPECT_EQ(by.at("none").false_detections, 1);
  for (const auto& [cls, s] : by) EXPECT_EQ(s.detections, 4) << cls;
  // The classes' false lines add up to every false line.
  int sum = 0;
  for (const auto& [cls, s] : by) sum += s.false_detections;
  EXPECT_EQ(sum, evaluation.overall().false_detections);
  // Frames whose nuisances are unknown leave the breakdown alone.
  evaluation.AddFrame(extracted, truths, matches, nullptr);
  EXPECT_EQ(evaluation.by_nuisance().at("none").detections, 4);
}

TEST(NuisanceTruthFile, ReadsSegmentsAndPerFrameShadowsInBaseLink) {
  const std::filesystem::path dir =
      std::filesystem::path(::testing::TempDir()) / "nuisance_truth_test";
  std::filesystem::create_directories(dir);
  {
    std::ofstream out(dir / "good.json");
    out << R"({"format": "groundline-nuisance-truth", "version": "1.0",
      "segments_map": [{"class": "tire_mark", "a_m": [10, 5], "b_m": [14, 5]},
                       {"class": "patch_seam", "a_m": [40, 0], "b_m": [41, 0]}],
      "vehicle_shadow_per_frame": [{"file": "000001.png",
        "polygon_base": [[0, 0], [1, 0], [1, 1]]}]})";
  }
  const core::Result<NuisanceTruth> truth = ReadNuisanceTruth(dir / "good.json");
  ASSERT_TRUE(truth.ok()) << truth.message();
  // The vehicle at (10, 4) facing +y: the tire mark runs 1 m ahead, across.
  const std::vector<NuisanceLine> seen = truth->InView(core::SE2(10, 4, M_PI / 2), "000001.png");
  ASSERT_EQ(seen.size(), 4u);  // the tire mark (the seam is 30 m away) and 3 shadow edges
  EXPECT_EQ(seen[0].cls, "tire_mark");
  EXPECT_NEAR(seen[0].a_m.x(), 1.0, 1e-12);
  EXPECT_NEAR(seen[0].a_m.y(), 0.0, 1e-12);
  EXPECT_NEAR(seen[0].b_m.y(), -4.0, 1e-12);
  EXPECT_EQ(seen[1].cls, "vehicle_shadow_edge");
  EXPECT_EQ(truth->InView(core::SE2(10, 4, 0), "other.png").size(), 1u);

  std::ofstream(dir / "bad.json") << R"({"format": "groundline-nuisance-truth",
      "segments_map": [{"class": "tire_mark", "a_m": [10], "b_m": [14, 5]}],
      "vehicle_shadow_per_frame": []})";
  const core::Result<NuisanceTruth> bad = ReadNuisanceTruth(dir / "bad.json");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("bad.json"), std::string::npos) << bad.message();
  EXPECT_NE(bad.message().find("segments_map"), std::string::npos) << bad.message();
}

}  // namespace
}  // namespace groundline::perception
