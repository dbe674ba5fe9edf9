// The atlas file: exact round trip, atomic write, errors that name the field;
// the surveyed atlas of a floor map (lines per segment, corner and crossing
// junctions).
#include "groundline/localization/atlas.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

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

TEST(Atlas, WriteThenReadIsExact) {
  Atlas atlas = AtlasFromFloorMap(SquareAndCross(), AtlasFromFloorMapOptions());
  atlas.lines[0].covariance << 2.5e-5, 1.0e-7, 1.0e-7, 4.0e-6;
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
