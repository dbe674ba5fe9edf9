#include "groundline/core/statistics.h"

#include <gtest/gtest.h>

#include <cmath>

namespace groundline::core {
namespace {

TEST(Median, IsNumpysMedian) {
  EXPECT_TRUE(std::isnan(Median({})));
  EXPECT_EQ(Median({3.0}), 3.0);
  EXPECT_EQ(Median({5.0, 1.0, 3.0}), 3.0);
  // np.median([4, 1, 3, 2]) == 2.5: the mean of the two middle values.
  EXPECT_EQ(Median({4.0, 1.0, 3.0, 2.0}), 2.5);
  EXPECT_EQ(Median({2.0, 2.0, 7.0, -1.0}), 2.0);
}

}  // namespace
}  // namespace groundline::core
