#include "groundline/sim/layout_png.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "groundline/sim/route.h"
#include "groundline/sim/zones.h"
#include "test_data.h"

namespace groundline::sim {
namespace {

// Writes the layout of each zone with a 1.2 km route (set GROUNDLINE_TEST_TMPDIR
// to keep them) and checks that the image has the predicted size and shows the
// trajectory and the floor where they are.
TEST(LayoutPng, DrawsEachZoneWithItsRoute) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("png");
  for (Zone zone : {Zone::kA, Zone::kB, Zone::kC, Zone::kD}) {
    const World world = *BuildZone(zone, 1);
    const core::Result<Route> route = GenerateRoute(world, RouteOptions{});
    ASSERT_TRUE(route.ok()) << route.message();
    const std::string name = std::string("zone_") + "abcd"[static_cast<int>(zone)] + ".png";
    LayoutPngOptions options;
    ASSERT_TRUE(WriteLayoutPng(world, &route->T_map_base, dir / name, options).ok());
    const cv::Mat image = cv::imread((dir / name).string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(image.empty()) << name;

    Vector2 lo = world.floor_min_m, hi = world.floor_max_m;
    for (const Obstacle& o : world.obstacles) {
      for (const Vector2& c : o.box.Corners()) {
        lo = lo.cwiseMin(c);
        hi = hi.cwiseMax(c);
      }
    }
    EXPECT_EQ(image.cols, static_cast<int>(std::ceil((hi.x() - lo.x() + 6.0) * 10.0)));
    EXPECT_EQ(image.rows, static_cast<int>(std::ceil((hi.y() - lo.y() + 6.0) * 10.0)));
    auto pixel = [&](const Vector2& p) {
      const int u = static_cast<int>((p.x() - lo.x() + 3.0) * 10.0);
      const int v = static_cast<int>((hi.y() + 3.0 - p.y()) * 10.0);
      return image.at<cv::Vec3b>(v, u);
    };
    // The trajectory is red along its length (skip the start marker).
    int red = 0, checked = 0;
    for (std::size_t k = 500; k < route->T_map_base.size(); k += 97) {
      const cv::Vec3b bgr = pixel(route->T_map_base[k].pose.translation());
      red += (bgr[2] > 150 && bgr[1] < 100 && bgr[0] < 100) ? 1 : 0;
      ++checked;
    }
    EXPECT_GT(red, 0.9 * checked) << name;
  }
}

TEST(LayoutPng, RefusesOversizedImages) {
  LayoutPngOptions options;
  options.pixels_per_m = 500.0;
  const core::Status status = WriteLayoutPng(*BuildZone(Zone::kB, 1), nullptr,
                                             ::groundline::testing::ScratchDir("big") / "b.png", options);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("max_side_px"), std::string::npos);
}

}  // namespace
}  // namespace groundline::sim
