// The atlas file: exact round trip, atomic write, errors that name the field;
// the surveyed atlas of a floor map (lines per segment, corner and crossing
// junctions).
#include "groundline/localization/atlas.h"

#include "groundline/localization/floor_association.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>
#include <random>

namespace groundline::localization {
namespace {

std::filesystem::path TempPath(const std::string& name) {
  return std::filesystem::path(::testing::TempDir()) / name;
}

core::FloorMap SquareAndCross() {
  core::FloorMap map;
  core::FloorMarking box;
  box.id = 1;
  box.kind = core::MarkingKind::kStagingBoxEdge;
  box.width_m = 0.05;
  box.polyline_m = {{0, 0}, {2, 0}, {2, 2}, {0, 2}, {0, 0}};
  core::FloorMarking tape;
  tape.id = 2;
  tape.width_m = 0.075;
  tape.polyline_m = {{1, -1}, {1, 3}};  // crosses the box's bottom and top edges
  map.markings = {box, tape};
  return map;
}

TEST(Atlas, FromFloorMapHasOneLinePerSegmentAndCornerAndCrossingJunctions) {
  const Atlas atlas = AtlasFromFloorMap(SquareAndCross(), AtlasFromFloorMapOptions());
  EXPECT_EQ(atlas.lines.size(), 5u);
  EXPECT_EQ(atlas.junctions.size(), 6u);  // 4 corners + 2 crossings
  ASSERT_TRUE(atlas.Validate().ok()) << atlas.Validate().message();
  bool found_crossing = false;
  for (const AtlasJunction& j : atlas.junctions) {
    found_crossing |= (j.point_m - Eigen::Vector2d(1.0, 2.0)).norm() < 1e-9;
  }
  EXPECT_TRUE(found_crossing);
}

// The covariance of LineCovarianceAbout is that of turning the line by
// N(0, sigma_rad^2) about the anchor and shifting it there by N(0, sigma_m^2):
// a Monte Carlo of that perturbation, far from the map origin.
TEST(Atlas, LineCovarianceAboutTheAnchorMatchesAMonteCarloOfTheSurveyError) {
  const Eigen::Vector2d anchor(80.7, 60.5);
  const perception::HesseLine line =
      *perception::LineFromPoints(anchor, anchor + Eigen::Vector2d(-3, 0.1));
  const Eigen::Matrix2d covariance = LineCovarianceAbout(line, anchor, 0.005, 0.002);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Matrix2d sample = Eigen::Matrix2d::Zero();
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const double turn_rad = 0.002 * normal(rng);
    const Eigen::Vector2d shifted = anchor + 0.005 * normal(rng) * line.Normal();
    const Eigen::Vector2d direction = Eigen::Rotation2Dd(turn_rad) * line.Direction();
    const perception::HesseLine perturbed =
        *perception::LineFromPoints(shifted, shifted + direction);
    const Eigen::Vector2d d = perception::LineDifference(perturbed, line);
    sample += d * d.transpose() / n;
  }
  EXPECT_NEAR(sample(0, 0), covariance(0, 0), 0.05 * covariance(0, 0));
  EXPECT_NEAR(sample(1, 1), covariance(1, 1), 0.05 * covariance(1, 1));
  EXPECT_NEAR(sample(0, 1), covariance(0, 1), 0.05 * std::abs(covariance(0, 1)));
  // Seen from the anchor the survey error is the stated one, uncorrelated.
  Eigen::Matrix2d J;
  perception::InverseTransformLine(core::SE2(anchor.x(), anchor.y(), 0.3), line, nullptr, &J);
  const Eigen::Matrix2d local = J * covariance * J.transpose();
  EXPECT_NEAR(local(0, 0), 0.005 * 0.005, 1e-12);
  EXPECT_NEAR(local(1, 1), 0.002 * 0.002, 1e-12);
  EXPECT_NEAR(local(0, 1), 0.0, 1e-12);
}

// Zone A (1.2 km, seed 11) at t = 508.5 s: the floor camera, driving west
// along the dashed tape at y = 61 m through a crosswalk 80 m from the map
// origin, reported one edge of the 0.5 m stripe at y = 60.5 m (glare beside
// it) as a plain tape 0.21 m from the stripe's centre line. With the survey
// error taken about the map origin, the stripe's 2 mrad direction error made
// 16 cm of rho at the vehicle, the 0.21 m innovation passed the gate
// (d2 = 3.4) and pulled the estimate 21 cm sideways for 2 s.
TEST(Atlas, AFarAwayStripeDoesNotOpenTheGateToItsEdge) {
  core::FloorMap map;
  core::FloorMarking stripe;
  stripe.id = 93;
  stripe.kind = core::MarkingKind::kCrosswalkStripe;
  stripe.width_m = 0.5;
  stripe.polyline_m = {{79.1667, 60.5}, {82.1667, 60.5}};
  map.markings = {stripe};
  const Atlas atlas = AtlasFromFloorMap(map, AtlasFromFloorMapOptions());
  ASSERT_EQ(atlas.lines.size(), 1u);
  const core::SE2 T_map_base(81.879, 61.013, 3.1313);  // the prediction, 1.3 cm off
  core::Matrix3 covariance = core::Vector3(3.28e-5, 1.87e-3, 9.82e-5).asDiagonal();
  LineObservation edge;
  edge.line_base = {0.2864, 1.5701};
  edge.covariance << 1.56e-6, -1.12e-6, -1.12e-6, 1.36e-6;
  edge.endpoint_a_base_m = {0.835, 0.286};
  edge.endpoint_b_base_m = {2.115, 0.285};
  const double d2 = LineMahalanobis2(edge, atlas.lines[0], T_map_base, covariance);
  EXPECT_GT(d2, 20.0);  // 0.21 m against a 4.3 cm lateral sigma
  EXPECT_EQ(AssociateLines({edge}, atlas, T_map_base, covariance, AssociationOptions())[0].landmark,
            -1);
  LineObservation centre = edge;  // the stripe's centre line, as the camera sees it
  centre.line_base.rho_m = 0.5042;
  EXPECT_EQ(
      AssociateLines({centre}, atlas, T_map_base, covariance, AssociationOptions())[0].landmark, 0);
}

TEST(Atlas, WriteThenReadIsExact) {
  Atlas atlas = AtlasFromFloorMap(SquareAndCross(), AtlasFromFloorMapOptions());
  atlas.lines[0].covariance << 2.5e-5, 1.0e-7, 1.0e-7, 4.0e-6;
  atlas.lines[1].seen = LandmarkSightings{7, 12.5, 98.25};
  atlas.junctions[2].seen = LandmarkSightings{2, 3.0, 3.5};
  atlas.lines[2].missed = 4;
  atlas.junctions[1].missed = 9;
  const auto path = TempPath("atlas_round_trip.json");
  ASSERT_TRUE(WriteAtlas(path, atlas).ok());
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
  const auto read = ReadAtlas(path);
  ASSERT_TRUE(read.ok()) << read.message();
  ASSERT_EQ(read->lines.size(), atlas.lines.size());
  ASSERT_EQ(read->junctions.size(), atlas.junctions.size());
  for (size_t i = 0; i < atlas.lines.size(); ++i) {
    EXPECT_EQ(read->lines[i].line_map.rho_m, atlas.lines[i].line_map.rho_m);
    EXPECT_EQ(read->lines[i].line_map.alpha_rad, atlas.lines[i].line_map.alpha_rad);
    EXPECT_EQ(read->lines[i].covariance, atlas.lines[i].covariance);
    EXPECT_EQ(read->lines[i].kind, atlas.lines[i].kind);
    EXPECT_EQ(read->lines[i].endpoint_b_m, atlas.lines[i].endpoint_b_m);
  }
  EXPECT_EQ(read->junctions[3].point_m, atlas.junctions[3].point_m);
  EXPECT_FALSE(read->lines[0].seen.has_value());
  ASSERT_TRUE(read->lines[1].seen.has_value());
  EXPECT_EQ(read->lines[1].seen->keyframes, 7);
  EXPECT_EQ(read->lines[1].seen->first_s, 12.5);
  EXPECT_EQ(read->lines[1].seen->last_s, 98.25);
  ASSERT_TRUE(read->junctions[2].seen.has_value());
  EXPECT_EQ(read->junctions[2].seen->keyframes, 2);
  EXPECT_EQ(read->lines[2].missed, 4);
  EXPECT_EQ(read->lines[1].missed, 0);
  EXPECT_EQ(read->junctions[1].missed, 9);
  EXPECT_FALSE(read->covariances_stated);
  atlas.covariances_stated = true;
  ASSERT_TRUE(WriteAtlas(path, atlas).ok());
  const auto stated = ReadAtlas(path);
  ASSERT_TRUE(stated.ok()) << stated.message();
  EXPECT_TRUE(stated->covariances_stated);
}

TEST(Atlas, ErrorsNameTheField) {
  const auto path = TempPath("atlas_bad.json");
  const auto write = [&](const std::string& text) {
    std::ofstream(path) << text;
    return ReadAtlas(path);
  };
  const std::string head = R"({"format": "groundline-atlas", "version_major": 1, "frame": "map",)";
  auto bad = write(head + R"("lines": [{"id": 0, "rho_m": "x", "alpha_rad": 0,
      "covariance": [1,0,0,1], "kind": "tape_solid", "endpoints_m": [0,0,1,0]}], "junctions": []})");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("lines[0].rho_m"), std::string::npos) << bad.message();
  bad = write(head + R"("lines": [], "junctions": [{"id": 0, "point_m": [1, 2],
      "covariance": [1, 0, 0, -1]}]})");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("junctions[0].covariance"), std::string::npos) << bad.message();
  bad = write(R"({"format": "something-else", "version_major": 1})");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("format"), std::string::npos) << bad.message();
  bad = write("{not json");
  EXPECT_FALSE(bad.ok());
  // A number beyond double's range is an error, not an exception out of the reader.
  bad = write(head + R"("lines": [{"id": 0, "rho_m": 4e406}], "junctions": []})");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("not valid JSON"), std::string::npos) << bad.message();
  // An id that no integer holds is an error naming it (not an undefined cast).
  for (const char* id : {"1e300", "0.5", "-9.3e18"}) {
    bad = write(head + R"("lines": [{"id": )" + id +
                R"(, "rho_m": 1, "alpha_rad": 0, "covariance": [1,0,0,1], "kind": "tape_solid",
        "endpoints_m": [0,0,1,0]}], "junctions": []})");
    ASSERT_FALSE(bad.ok()) << id;
    EXPECT_NE(bad.message().find("lines[0].id': expected an integer id"), std::string::npos)
        << bad.message();
  }
  // covariances_stated is optional (a file written before it reads as not
  // stated), and a boolean when present.
  const auto older = write(head + R"("lines": [], "junctions": []})");
  ASSERT_TRUE(older.ok()) << older.message();
  EXPECT_FALSE(older->covariances_stated);
  // A landmark's sightings: keyframes >= 1, last_s not before first_s.
  bad = write(head + R"("lines": [{"id": 0, "rho_m": 1, "alpha_rad": 0, "covariance": [1,0,0,1],
      "kind": "tape_solid", "endpoints_m": [0,0,1,0],
      "seen": {"keyframes": 3, "first_s": 9, "last_s": 2}}], "junctions": []})");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("lines[0].seen.last_s"), std::string::npos) << bad.message();
  bad = write(head + R"("lines": [], "junctions": [{"id": 0, "point_m": [1, 2],
      "covariance": [1, 0, 0, 1], "seen": {"keyframes": 0, "first_s": 1, "last_s": 2}}]})");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("junctions[0].seen.keyframes"), std::string::npos) << bad.message();
  bad = write(head + R"("lines": [{"id": 0, "rho_m": 1, "alpha_rad": 0, "covariance": [1,0,0,1],
      "kind": "tape_solid", "endpoints_m": [0,0,1,0], "missed": -2}], "junctions": []})");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("lines[0].missed"), std::string::npos) << bad.message();
  bad = write(head + R"("covariances_stated": "yes", "lines": [], "junctions": []})");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("covariances_stated"), std::string::npos) << bad.message();
  EXPECT_FALSE(ReadAtlas(TempPath("does_not_exist.json")).ok());
}

TEST(Atlas, InvalidAtlasIsNotWritten) {
  Atlas atlas;
  atlas.lines.push_back(AtlasLine{});
  atlas.lines.push_back(AtlasLine{});  // duplicate id 0
  const auto path = TempPath("atlas_invalid.json");
  const core::Status status = WriteAtlas(path, atlas);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("lines[1].id"), std::string::npos) << status.message();
  EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace groundline::localization
