// Tire scuffs of the floor renderer (sim/src/floor_camera_internal.h,
// ScuffField): curved streaks of any orientation, with the mean darkening of
// the former straight streaks, seeded and periodic.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "floor_camera_internal.h"
#include "groundline/core/random_draws.h"

namespace groundline::sim::internal {
namespace {

// E[D(p) D(p + lag)] / E[D(p)^2] over random p: how far a streak continues.
double Autocorrelation(const ScuffField& field, const Vector2& lag_m, int samples,
                       std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-100.0, 100.0);
  double cross = 0.0, square = 0.0;
  for (int i = 0; i < samples; ++i) {
    const Vector2 p = core::DrawVector<2>(u, rng);
    const double d = field.Darkening(p);
    if (d == 0.0) continue;
    cross += d * field.Darkening(p + lag_m);
    square += d * d;
  }
  return cross / square;
}

TEST(FloorScuffs, MeanDarkeningOfTheFormerStreaks) {
  const ScuffField field(5, true);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(0.0, ScuffField::kPeriodM);
  double sum = 0.0;
  constexpr int kSamples = 100000;
  for (int i = 0; i < kSamples; ++i) sum += field.Darkening(core::DrawVector<2>(u, rng));
  // Overlapping arcs darken by their maximum, a little less than the sum.
  EXPECT_NEAR(sum / kSamples, ScuffField::kMeanDarkening, 0.15 * ScuffField::kMeanDarkening);
}

TEST(FloorScuffs, NoPreferredDirection) {
  const ScuffField field(5, true);
  constexpr double kLagM = 0.3;
  const double along_x = Autocorrelation(field, Vector2(kLagM, 0.0), 100000, 2);
  const double along_y = Autocorrelation(field, Vector2(0.0, kLagM), 100000, 3);
  const double diagonal = Autocorrelation(field, Vector2(kLagM, kLagM) / std::sqrt(2.0), 100000, 4);
  // Streaks run on: at 30 cm a scuff is still there in some direction ...
  EXPECT_GT(along_x, 0.01);
  // ... but no axis is special (straight streaks along x gave ~0.7 along x).
  EXPECT_NEAR(along_x / diagonal, 1.0, 0.3);
  EXPECT_NEAR(along_y / diagonal, 1.0, 0.3);
  EXPECT_LT(along_x, 0.2);
}

TEST(FloorScuffs, SeededPeriodicAndSoft) {
  const ScuffField a(5, true), b(5, true), c(6, true), off(5, false);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-200.0, 200.0);
  int dark = 0, differ = 0, soft = 0;
  for (int i = 0; i < 50000; ++i) {
    const Vector2 p = core::DrawVector<2>(u, rng);
    const float d = a.Darkening(p);
    EXPECT_GE(d, 0.0f);
    EXPECT_LE(d, 1.0f);
    EXPECT_EQ(d, b.Darkening(p));
    EXPECT_NEAR(d, a.Darkening(p + Vector2(ScuffField::kPeriodM, -ScuffField::kPeriodM)), 1e-4);
    EXPECT_EQ(off.Darkening(p), 0.0f);
    if (d > 0.0f) ++dark;
    if (d > 0.0f && d < 0.5f) ++soft;
    if (d != c.Darkening(p)) ++differ;
  }
  EXPECT_GT(dark, 1000);
  EXPECT_GT(soft, dark / 4);  // soft edges and tapered ends, not hard bands
  EXPECT_GT(differ, dark);    // another seed, other scuffs
}

}  // namespace
}  // namespace groundline::sim::internal
