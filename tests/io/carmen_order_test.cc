// OrderLaserScans: the scans of a log in strictly increasing stamp order,
// each late scan within the window put in its place, later ones and
// duplicates dropped and counted.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "groundline/io/carmen_order.h"

namespace groundline::io {
namespace {

std::vector<CarmenLaserScan> ScansAt(const std::vector<double>& stamps_s) {
  std::vector<CarmenLaserScan> scans(stamps_s.size());
  for (std::size_t i = 0; i < stamps_s.size(); ++i) {
    scans[i].stamp_s = stamps_s[i];
    scans[i].line = static_cast<std::int64_t>(i) + 1;
  }
  return scans;
}

std::vector<const CarmenLaserScan*> Pointers(const std::vector<CarmenLaserScan>& scans) {
  std::vector<const CarmenLaserScan*> p;
  for (const CarmenLaserScan& s : scans) p.push_back(&s);
  return p;
}

std::vector<double> Stamps(const CarmenScanOrder& order) {
  std::vector<double> stamps;
  for (const CarmenLaserScan* s : order.scans) stamps.push_back(s->stamp_s);
  return stamps;
}

TEST(CarmenScanOrder, ScansInOrderComeOutUnchanged) {
  const std::vector<CarmenLaserScan> scans = ScansAt({0.0, 0.1, 0.2, 0.3, 5.0, 5.1});
  const core::Result<CarmenScanOrder> order = OrderLaserScans(Pointers(scans));
  ASSERT_TRUE(order.ok()) << order.message();
  EXPECT_EQ(order->scans, Pointers(scans));
  EXPECT_EQ(order->reordered + order->dropped_late + order->dropped_duplicate, 0);
  EXPECT_EQ(order->first_reordered_line, 0);
  EXPECT_EQ(order->first_dropped_line, 0);
}

TEST(CarmenScanOrder, SwappedNeighboursTakeTheirPlace) {
  // Lines 3 and 4 swapped, and 7 written after 8 and 9.
  const std::vector<CarmenLaserScan> scans =
      ScansAt({0.0, 0.1, 0.3, 0.2, 0.4, 0.5, 0.8, 0.9, 0.6, 0.7});
  const core::Result<CarmenScanOrder> order = OrderLaserScans(Pointers(scans));
  ASSERT_TRUE(order.ok()) << order.message();
  EXPECT_EQ(Stamps(*order),
            (std::vector<double>{0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9}));
  EXPECT_EQ(order->reordered, 3);  // 0.2 after 0.3; 0.6 and 0.7 after 0.9
  EXPECT_NEAR(order->max_delay_s, 0.3, 1e-12);
  EXPECT_EQ(order->first_reordered_line, 4);
  EXPECT_EQ(order->dropped_late + order->dropped_duplicate, 0);
}

TEST(CarmenScanOrder, AScanLaterThanTheWindowIsDroppedNeverMovedBack) {
  // Line 5 (0.15 s) arrives after 2.0 s of newer scans.
  const std::vector<CarmenLaserScan> scans = ScansAt({0.0, 0.1, 1.0, 2.2, 0.15, 2.3});
  const core::Result<CarmenScanOrder> order = OrderLaserScans(Pointers(scans), {.window_s = 1.0});
  ASSERT_TRUE(order.ok()) << order.message();
  EXPECT_EQ(Stamps(*order), (std::vector<double>{0.0, 0.1, 1.0, 2.2, 2.3}));
  EXPECT_EQ(order->dropped_late, 1);
  EXPECT_EQ(order->first_dropped_line, 5);
  EXPECT_EQ(order->reordered, 0);
  // With a window of 3 s it is kept, in its place.
  const core::Result<CarmenScanOrder> wide = OrderLaserScans(Pointers(scans), {.window_s = 3.0});
  ASSERT_TRUE(wide.ok());
  EXPECT_EQ(Stamps(*wide), (std::vector<double>{0.0, 0.1, 0.15, 1.0, 2.2, 2.3}));
  EXPECT_EQ(wide->reordered, 1);
  EXPECT_NEAR(wide->max_delay_s, 2.05, 1e-12);
}

TEST(CarmenScanOrder, DuplicateStampsKeepTheFirstScan) {
  // 0.2 twice in a row (held together), and again after 0.2 was released.
  const std::vector<CarmenLaserScan> scans = ScansAt({0.0, 0.1, 0.2, 0.2, 1.5, 0.2, 1.6});
  const core::Result<CarmenScanOrder> order = OrderLaserScans(Pointers(scans), {.window_s = 1.0});
  ASSERT_TRUE(order.ok()) << order.message();
  EXPECT_EQ(Stamps(*order), (std::vector<double>{0.0, 0.1, 0.2, 1.5, 1.6}));
  EXPECT_EQ(order->scans[2]->line, 3);  // the first of the two at 0.2
  EXPECT_EQ(order->dropped_duplicate, 2);
  EXPECT_EQ(order->dropped_late, 0);
}

// The invariant on a shuffled log: every scan displaced by less than the
// window is kept, and the output is the sorted input.
TEST(CarmenScanOrder, ALogShuffledWithinTheWindowComesOutSorted) {
  std::vector<double> stamps;
  for (int i = 0; i < 2000; ++i) stamps.push_back(0.025 * i);  // a 40 Hz laser
  std::mt19937 rng(5);
  std::vector<double> shuffled = stamps;
  for (std::size_t i = 0; i + 8 < shuffled.size(); i += 8) {  // within blocks of 8 scans
    std::shuffle(shuffled.begin() + static_cast<long>(i),
                 shuffled.begin() + static_cast<long>(i + 8), rng);
  }
  const std::vector<CarmenLaserScan> scans = ScansAt(shuffled);
  const core::Result<CarmenScanOrder> order = OrderLaserScans(Pointers(scans), {.window_s = 0.25});
  ASSERT_TRUE(order.ok()) << order.message();
  EXPECT_EQ(Stamps(*order), stamps);
  EXPECT_EQ(order->dropped_late + order->dropped_duplicate, 0);
  EXPECT_GT(order->reordered, 500);
  EXPECT_LT(order->max_delay_s, 0.25);
  // Without a window, a scan older than one already taken is dropped; what is
  // left still increases.
  const core::Result<CarmenScanOrder> none = OrderLaserScans(Pointers(scans), {.window_s = 0.0});
  ASSERT_TRUE(none.ok());
  const std::vector<double> kept = Stamps(*none);
  EXPECT_TRUE(std::adjacent_find(kept.begin(), kept.end(), std::greater_equal<>()) == kept.end());
  EXPECT_EQ(static_cast<std::int64_t>(kept.size()) + none->dropped_late, 2000);
  EXPECT_GT(none->dropped_late, 500);
}

TEST(CarmenScanOrder, BadInputIsNamed) {
  std::vector<CarmenLaserScan> scans = ScansAt({0.0, 0.1});
  scans[1].stamp_s = std::numeric_limits<double>::quiet_NaN();
  core::Result<CarmenScanOrder> order = OrderLaserScans(Pointers(scans));
  ASSERT_FALSE(order.ok());
  EXPECT_NE(order.message().find("line 2"), std::string::npos) << order.message();
  order = OrderLaserScans(Pointers(scans), {.window_s = -1.0});
  ASSERT_FALSE(order.ok());
  EXPECT_NE(order.message().find("window_s"), std::string::npos) << order.message();
}

}  // namespace
}  // namespace groundline::io
