#include "groundline/io/relations.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "test_data.h"

namespace groundline::io {
namespace {

namespace fs = std::filesystem;
using groundline::testing::ScratchDir;
using groundline::testing::SharedDataDir;

constexpr double kTol = 1e-9;

fs::path WriteFile(const std::string& name, const std::vector<std::string>& lines) {
  const fs::path path = ScratchDir(name) / (name + ".relations");
  std::ofstream out(path);
  for (const std::string& line : lines) out << line << '\n';
  return path;
}

void ExpectRelation(const core::Relation& r, double t1, double t2, double x, double y, double yaw) {
  EXPECT_NEAR(r.t1_s, t1, 1e-6);  // absolute stamps (mit-csail) keep ~1e-7 s
  EXPECT_NEAR(r.t2_s, t2, 1e-6);
  EXPECT_NEAR(r.delta.x(), x, kTol);
  EXPECT_NEAR(r.delta.y(), y, kTol);
  EXPECT_NEAR(r.delta.yaw(), yaw, kTol);
}

// Line counts from `wc -l`; first and last lines from head / tail.
TEST(Relations, AcesFile) {
  GROUNDLINE_REQUIRE_DATA("lidar2d/aces.relations");
  core::Result<std::vector<core::Relation>> relations =
      ReadRelations(SharedDataDir() / "lidar2d" / "aces.relations");
  ASSERT_TRUE(relations.ok()) << relations.message();
  ASSERT_EQ(relations->size(), 1279u);
  // 90.239599 90.719599 0.422330 -0.000750 0.000000 0.000000 0.000000 0.017260
  ExpectRelation(relations->front(), 90.239599, 90.719599, 0.422330, -0.000750, 0.017260);
  // 305.610000 1374.009999 1.017670 -0.103740 0.000000 0.000000 0.000000 -1.222240
  ExpectRelation(relations->back(), 305.61, 1374.009999, 1.017670, -0.103740, -1.222240);
}

TEST(Relations, MitCsailFile) {
  GROUNDLINE_REQUIRE_DATA("lidar2d/mit-csail.relations");
  core::Result<std::vector<core::Relation>> relations =
      ReadRelations(SharedDataDir() / "lidar2d" / "mit-csail.relations");
  ASSERT_TRUE(relations.ok()) << relations.message();
  ASSERT_EQ(relations->size(), 1172u);
  // 1134864645.90321 1134864646.32420 0.31293 0.02935 0.00000  0.00000 0.00000 0.24198
  ExpectRelation(relations->front(), 1134864645.90321, 1134864646.32420, 0.31293, 0.02935, 0.24198);
  // 1134864686.65618 1134865034.47520 0.69012 0.56141 0.00000  0.00000 0.00000 -0.57907
  ExpectRelation(relations->back(), 1134864686.65618, 1134865034.47520, 0.69012, 0.56141, -0.57907);
}

TEST(Relations, CommentsAndBlankLinesAreSkipped) {
  const fs::path path =
      WriteFile("comments", {"# t1 t2 x y z roll pitch yaw", "", "1 2 0.5 -0.25 0 0 0 3.0", "  ",
                             "2 3 1e-1 0 0 -0 +0 -3.0"});
  core::Result<std::vector<core::Relation>> relations = ReadRelations(path);
  ASSERT_TRUE(relations.ok()) << relations.message();
  ASSERT_EQ(relations->size(), 2u);
  ExpectRelation((*relations)[0], 1, 2, 0.5, -0.25, 3.0);
  ExpectRelation((*relations)[1], 2, 3, 0.1, 0.0, -3.0);
}

TEST(Relations, MalformedLinesNameFileLineAndField) {
  struct Case {
    std::string line;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {"1 2 0.5 0.1 0 0 0", "expected 8 fields 't1 t2 x y z roll pitch yaw', got 7 (truncated"},
      {"1 2 0.5 0.1 0 0 0 0.2 9", "expected 8 fields"},
      {"1 2 0.5 abc 0 0 0 0.2", "field 'y' (field 4): expected a finite number, got 'abc'"},
      {"1 2 0.5 0.1 0 0 0 inf", "field 'yaw' (field 8): expected a finite number"},
      {"1 2 0.5 0.1 0.3 0 0 0.2", "field 'z' (field 5): expected 0 for a planar relation"},
      {"1 2 0.5 0.1 0 0 1e-6 0.2", "field 'pitch' (field 7): expected 0"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE(cases[i].line);
    const fs::path path =
        WriteFile("bad" + std::to_string(i), {"0 1 0 0 0 0 0 0", "", cases[i].line});
    core::Result<std::vector<core::Relation>> relations = ReadRelations(path);
    ASSERT_FALSE(relations.ok());
    EXPECT_EQ(relations.message().rfind(path.string() + ":3: ", 0), 0u) << relations.message();
    EXPECT_NE(relations.message().find(cases[i].expected), std::string::npos)
        << relations.message();
  }
}

TEST(Relations, OutOfPlaneToleranceIsAnOption) {
  const fs::path path = WriteFile("tolerance", {"1 2 0.5 0.1 0 0 1e-6 0.2"});
  RelationsReadOptions options;
  options.max_out_of_plane = 1e-5;
  EXPECT_TRUE(ReadRelations(path, options).ok());
  options.max_out_of_plane = -1.0;
  EXPECT_FALSE(options.Validate().ok());
  EXPECT_FALSE(ReadRelations(path, options).ok());
}

}  // namespace
}  // namespace groundline::io
