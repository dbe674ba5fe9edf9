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

// Reference values: the standard tables (Abramowitz and Stegun 26.2, 26.4).
TEST(NormalQuantile, MatchesTheTablesInBothTails) {
  EXPECT_NEAR(NormalQuantile(0.5), 0.0, 1e-12);
  EXPECT_NEAR(NormalQuantile(0.975), 1.959963985, 1e-8);
  EXPECT_NEAR(NormalQuantile(0.9999), 3.719016485, 1e-8);
  EXPECT_NEAR(NormalQuantile(0.01), -2.326347874, 1e-8);
  EXPECT_NEAR(NormalQuantile(0.8), 0.841621234, 1e-8);
  EXPECT_TRUE(std::isnan(NormalQuantile(0.0)));
  EXPECT_TRUE(std::isnan(NormalQuantile(1.0)));
}

TEST(ChiSquareQuantile, ExactForOneAndTwoDofWithinFourPercentAbove) {
  EXPECT_NEAR(ChiSquareQuantile(1, 0.99), 6.634897, 1e-5);
  EXPECT_NEAR(ChiSquareQuantile(1, 0.9999), 15.136705, 1e-5);
  EXPECT_NEAR(ChiSquareQuantile(2, 0.99), 9.210340, 1e-5);
  EXPECT_NEAR(ChiSquareQuantile(2, 0.9999), 18.420681, 1e-5);
  struct Case {
    int dof;
    double p, exact;
  };
  for (const Case& c : {Case{3, 0.99, 11.344867}, Case{3, 0.9999, 21.107513},
                        Case{4, 0.999, 18.466827}, Case{4, 0.9999, 23.512742},
                        Case{6, 0.9, 10.644641}}) {
    const double q = ChiSquareQuantile(c.dof, c.p);
    EXPECT_GE(q, c.exact * 0.995) << c.dof << " dof, p " << c.p;
    EXPECT_LE(q, c.exact * 1.04) << c.dof << " dof, p " << c.p;
  }
  EXPECT_TRUE(std::isnan(ChiSquareQuantile(0, 0.9)));
}

}  // namespace
}  // namespace groundline::core
