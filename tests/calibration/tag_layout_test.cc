// The tag layout file: round trip, and errors that name the file, line and field.
#include "groundline/calibration/tag_layout.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <numbers>
#include <string>

#include "test_data.h"

namespace groundline::calibration {
namespace {

constexpr char kGood[] = R"(format: groundline-tag-layout
version: "1.0"
family: tag36h11
frame: floor
tags:
  - {id: 3, size_m: 0.16, pose: {x_m: 1.25, y_m: -0.3, yaw_rad: 0.5}}
  - id: 4
    size_m: 0.16
    pose: {x_m: 1.6, y_m: 0.3, yaw_rad: -3.0}
vehicle_poses:
  - {image: a.png, pose: {x_m: -0.5, y_m: 0.02, yaw_rad: 0.01}}
  - {image: b.png, pose: {x_m: 0.0, y_m: 0.0, yaw_rad: 0.0}}
)";

TEST(TagLayout, ParsesTheDocumentedExample) {
  core::Result<TagLayout> layout = ParseTagLayoutYaml(kGood, "layout.yaml");
  ASSERT_TRUE(layout.ok()) << layout.message();
  EXPECT_EQ(layout->frame, TagLayoutFrame::kFloor);
  ASSERT_EQ(layout->tags.size(), 2u);
  EXPECT_EQ(layout->tags[1].id, 4);
  EXPECT_DOUBLE_EQ(layout->tags[0].T_frame_tag.yaw(), 0.5);
  ASSERT_NE(layout->FindPose("b.png"), nullptr);
  EXPECT_EQ(layout->FindPose("c.png"), nullptr);
  EXPECT_DOUBLE_EQ(layout->FindPose("a.png")->T_floor_base.x(), -0.5);
  ASSERT_NE(layout->FindTag(3), nullptr);
  EXPECT_EQ(layout->FindTag(5), nullptr);
}

TEST(TagLayout, OptionalSurveyErrorIsReadWrittenAndChecked) {
  EXPECT_DOUBLE_EQ(ParseTagLayoutYaml(kGood, "layout.yaml").value().survey_sigma_m, 0.0);
  std::string text = kGood;
  text.insert(text.find("tags:"), "survey_sigma_m: 0.0015\n");
  const TagLayout layout = ParseTagLayoutYaml(text, "layout.yaml").value();
  EXPECT_DOUBLE_EQ(layout.survey_sigma_m, 0.0015);
  const core::Result<TagLayout> back = ParseTagLayoutYaml(TagLayoutToYaml(layout), "written.yaml");
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_DOUBLE_EQ(back->survey_sigma_m, 0.0015);
  std::string negative = kGood;
  negative.insert(negative.find("tags:"), "survey_sigma_m: -1\n");
  const core::Result<TagLayout> bad = ParseTagLayoutYaml(negative, "layout.yaml");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("layout.yaml:5: field 'survey_sigma_m'"), std::string::npos)
      << bad.message();
}

TEST(TagLayout, CornersFollowLibapriltagOrderInTheTagFrame) {
  SurveyedTag tag{7, 0.2, core::SE2(1.0, 2.0, std::numbers::pi / 2)};
  const auto c = tag.CornersInFrame();
  // Tag x (printed right) points along floor +y, tag y (printed top) along floor -x.
  EXPECT_TRUE(c[0].isApprox(Eigen::Vector2d(1.1, 1.9)));  // bottom-left
  EXPECT_TRUE(c[1].isApprox(Eigen::Vector2d(1.1, 2.1)));  // bottom-right
  EXPECT_TRUE(c[2].isApprox(Eigen::Vector2d(0.9, 2.1)));  // top-right
  EXPECT_TRUE(c[3].isApprox(Eigen::Vector2d(0.9, 1.9)));  // top-left
}

TEST(TagLayout, WritesAndReadsBackExactly) {
  TagLayout layout = ParseTagLayoutYaml(kGood, "layout.yaml").value();
  layout.tags[0].T_frame_tag = core::SE2(0.1 + 0.2, 1.0 / 3.0, -2.718281828459045);
  const std::filesystem::path path = ::groundline::testing::ScratchDir("tag_layout") / "layout.yaml";
  ASSERT_TRUE(WriteTagLayout(layout, path).ok());
  core::Result<TagLayout> back = ReadTagLayout(path);
  ASSERT_TRUE(back.ok()) << back.message();
  ASSERT_EQ(back->tags.size(), layout.tags.size());
  for (std::size_t i = 0; i < layout.tags.size(); ++i) {
    EXPECT_EQ(back->tags[i].id, layout.tags[i].id);
    EXPECT_EQ(back->tags[i].size_m, layout.tags[i].size_m);
    EXPECT_TRUE(back->tags[i].T_frame_tag.IsApprox(layout.tags[i].T_frame_tag, 0.0, 0.0));
  }
  ASSERT_EQ(back->vehicle_poses.size(), 2u);
  EXPECT_EQ(back->vehicle_poses[1].image, "b.png");
  // Names the writer cannot quote are refused.
  TagLayout quoted = layout;
  quoted.vehicle_poses[0].image = "a\"b.png";
  EXPECT_FALSE(WriteTagLayout(quoted, path).ok());
  // base_link layouts have no poses.
  layout.frame = TagLayoutFrame::kBaseLink;
  layout.vehicle_poses.clear();
  ASSERT_TRUE(WriteTagLayout(layout, path).ok());
  back = ReadTagLayout(path);
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(back->frame, TagLayoutFrame::kBaseLink);
}

// Replaces the first occurrence of `from` in the good file.
std::string Edit(const std::string& from, const std::string& to) {
  std::string text = kGood;
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(TagLayout, MalformedFilesNameFileLineAndField) {
  const struct {
    std::string text;
    std::string expected;
  } cases[] = {
      {Edit("format: groundline-tag-layout", "format: other"), "layout.yaml:1: field 'format'"},
      {Edit("version: \"1.0\"", "version: \"2.0\""), "layout.yaml:2: field 'version'"},
      {Edit("family: tag36h11", "family: tag25h9"), "layout.yaml:3: field 'family'"},
      {Edit("frame: floor", "frame: map"), "field 'frame': expected 'floor' or 'base_link'"},
      {Edit("size_m: 0.16,", "size_m: -0.16,"), "layout.yaml:6: field 'tags[0].size_m'"},
      {Edit("x_m: 1.25", "x_m: abc"), "layout.yaml:6: field 'tags[0].pose.x_m': expected a finite"},
      {Edit("  - id: 4", "  - id: 3"), "layout.yaml:7: field 'tags[1].id'"},
      {Edit("{id: 3,", "{id: 587,"), "field 'tags[0].id': expected a tag36h11 id in 0..586"},
      {Edit("yaw_rad: 0.5}", "yaw: 0.5}"), "unknown key 'yaw' in 'tags[0].pose'"},
      {Edit("image: b.png", "image: a.png"), "layout.yaml:12: field 'vehicle_poses[1].image'"},
      // The writer quotes image names: one with a quote could not be written back.
      {Edit("image: b.png", "image: 'b\"1.png'"),
       "layout.yaml:12: field 'vehicle_poses[1].image': expected an image file name without"},
      {Edit("vehicle_poses:", "vehicle_pose:"), "unknown key 'vehicle_pose'"},
      {Edit("frame: floor", "frame: base_link"),
       "field 'vehicle_poses': expected no vehicle_poses"},
      {Edit("tags:\n", "tags: []\nx:\n"), "unknown key 'x'"},
      {Edit("    size_m: 0.16\n", ""), "missing key 'size_m' in 'tags[1]'"},
      {"format: [", "layout.yaml:1: YAML syntax error"},
      {"- a\n- b\n", "layout.yaml: expected a mapping"},
  };
  for (const auto& c : cases) {
    core::Result<TagLayout> r = ParseTagLayoutYaml(c.text, "layout.yaml");
    ASSERT_FALSE(r.ok()) << c.text;
    EXPECT_NE(r.message().find(c.expected), std::string::npos)
        << "got: " << r.message() << "\nexpected to contain: " << c.expected;
  }
  // A floor layout without poses.
  std::string no_poses = kGood;
  no_poses = no_poses.substr(0, no_poses.find("vehicle_poses:"));
  core::Result<TagLayout> r = ParseTagLayoutYaml(no_poses, "layout.yaml");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("frame: floor needs 'vehicle_poses'"), std::string::npos);
  EXPECT_NE(ReadTagLayout("/nonexistent/layout.yaml").message().find("cannot open"),
            std::string::npos);
}

}  // namespace
}  // namespace groundline::calibration
