// ActiveSubmaps (lidar/submaps.h): a front end without loop closures
// releases finished submaps, so its memory stays flat over a shift.
#include "groundline/localization/lidar/submaps.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace groundline::localization::lidar {
namespace {

ScanPoints Wall() {
  ScanPoints scan;
  for (int i = -20; i <= 20; ++i) {
    ScanPoint p;
    p.point_m = core::Vector2(3.0, 0.1 * i);
    scan.points.push_back(p);
  }
  return scan;
}

long Retained(const ActiveSubmaps& submaps) {
  return std::count_if(submaps.all().begin(), submaps.all().end(),
                       [](const auto& s) { return s != nullptr; });
}

TEST(ActiveSubmaps, ReleasesFinishedSubmapsWhenAskedAndKeepsThemOtherwise) {
  constexpr int kScansPerSubmap = 5;
  ActiveSubmaps released(ProbabilityGridOptions(), kScansPerSubmap, /*retain_finished=*/false);
  ActiveSubmaps retained(ProbabilityGridOptions(), kScansPerSubmap, /*retain_finished=*/true);
  int finished_released = 0, finished_retained = 0;
  for (int k = 0; k < 100; ++k) {
    const core::SE2 pose(0.05 * k, 0.0, 0.0);
    std::vector<std::shared_ptr<Submap>> finished;
    const std::vector<int> ids = released.InsertScan(pose, Wall(), &finished);
    // Every submap a scan went into, and every one that just finished, is
    // still there for the caller.
    for (int id : ids) ASSERT_NE(released.all()[static_cast<std::size_t>(id)], nullptr);
    for (const auto& f : finished)
      ASSERT_NE(released.all()[static_cast<std::size_t>(f->id)], nullptr);
    finished_released += static_cast<int>(finished.size());
    finished.clear();
    retained.InsertScan(pose, Wall(), &finished);
    finished_retained += static_cast<int>(finished.size());
  }
  EXPECT_EQ(finished_released, finished_retained);
  EXPECT_GT(finished_released, 15);
  EXPECT_EQ(released.all().size(), retained.all().size());
  EXPECT_LE(Retained(released), 3);  // the two active ones and the one that just finished
  EXPECT_EQ(Retained(retained), static_cast<long>(retained.all().size()));
}

}  // namespace
}  // namespace groundline::localization::lidar
