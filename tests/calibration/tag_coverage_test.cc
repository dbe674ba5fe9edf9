#include "groundline/calibration/tag_coverage.h"

#include <gtest/gtest.h>

namespace groundline::calibration {
namespace {

TagLayout ThreeTags() {
  TagLayout layout;
  layout.frame = TagLayoutFrame::kBaseLink;
  for (int id : {3, 5, 8}) layout.tags.push_back({id, 0.16, core::SE2(0.5 * id, 0.0, 0.0)});
  return layout;
}

TEST(TagCoverage, KeepsFramesUntilEveryTagHasEnoughAndSaysWhichAreMissing) {
  TagCoverage coverage(ThreeTags(), 2);
  EXPECT_EQ(coverage.Missing(),
            (std::vector<std::string>{"not yet seen: tags 3 5 8: point the camera at them (or move "
                                      "the vehicle)"}));
  const TagCoverage::Verdict first = coverage.Consider({5, 3, 40});
  EXPECT_TRUE(first.kept);
  EXPECT_EQ(first.layout_ids, (std::vector<int>{3, 5}));
  EXPECT_EQ(first.unknown_ids, (std::vector<int>{40}));
  EXPECT_NE(coverage.StatusLine().find("1 frames; tags seen 2 of 3"), std::string::npos)
      << coverage.StatusLine();
  EXPECT_EQ(coverage.Missing(),
            (std::vector<std::string>{
                "not yet seen: tags 8: point the camera at them (or move the vehicle)",
                "need more frames of: tag 3 (1 of 2), tag 5 (1 of 2)"}));

  const TagCoverage::Verdict nothing = coverage.Consider({40});
  EXPECT_FALSE(nothing.kept);
  EXPECT_EQ(nothing.reason, "no tag of the layout in view (tags 40 are not in it)");
  EXPECT_TRUE(coverage.Consider({3, 5}).kept);
  const TagCoverage::Verdict enough = coverage.Consider({3, 5});
  EXPECT_FALSE(enough.kept);
  EXPECT_NE(enough.reason.find("already have 2 frames"), std::string::npos);
  EXPECT_FALSE(coverage.Complete());
  EXPECT_TRUE(coverage.Consider({8, 3}).kept);  // 3 rides along with the needed 8
  EXPECT_TRUE(coverage.Consider({8}).kept);
  EXPECT_TRUE(coverage.Complete());
  EXPECT_EQ(coverage.frames(), 4);
  EXPECT_NE(coverage.StatusLine().find("coverage complete"), std::string::npos);
}

}  // namespace
}  // namespace groundline::calibration
