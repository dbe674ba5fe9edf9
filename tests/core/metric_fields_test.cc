#include "groundline/core/metric_fields.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace groundline::core {
namespace {

std::vector<std::string> Keys(const std::vector<MetricField>& fields) {
  std::vector<std::string> keys;
  for (const MetricField& f : fields) keys.push_back(f.key);
  return keys;
}

const MetricField* Find(const std::vector<MetricField>& fields, const std::string& key) {
  for (const MetricField& f : fields) {
    if (f.key == key) return &f;
  }
  return nullptr;
}

Trajectory Straight(std::size_t n) {
  Trajectory trajectory;
  for (std::size_t i = 0; i < n; ++i) {
    trajectory.push_back(
        {0.1 * static_cast<double>(i), SE2(0.1 * static_cast<double>(i), 0, 0), std::nullopt});
  }
  return trajectory;
}

TEST(MetricFields, TrajectoryKeysAreThoseOfEvalMd) {
  const Trajectory reference = Straight(30);
  Trajectory estimate = reference;
  for (StampedPose& p : estimate) p.pose = SE2(p.pose.x() + 0.1, 0.05, 0.0);
  const Result<TrajectoryErrorSummary> s = ComputeTrajectoryErrors(estimate, reference);
  ASSERT_TRUE(s.ok());
  const std::vector<MetricField> fields = MetricFields(*s);
  const std::vector<std::string> expected = {
      "n_matched", "n_unmatched",  "ate_rmse_m",   "ate_mean_m",       "ate_median_m",
      "ate_max_m", "along_rmse_m", "cross_rmse_m", "heading_rmse_deg", "n_tangent_from_heading"};
  EXPECT_EQ(Keys(fields), expected);
  EXPECT_TRUE(Find(fields, "n_matched")->is_count);
  EXPECT_DOUBLE_EQ(Find(fields, "n_matched")->value, 30.0);
  EXPECT_NEAR(Find(fields, "along_rmse_m")->value, 0.1, 1e-12);
  EXPECT_NEAR(Find(fields, "cross_rmse_m")->value, 0.05, 1e-12);
  EXPECT_EQ(Find(fields, "nees_in_band"), nullptr);  // no covariances
}

TEST(MetricFields, OptionalGroupsAppearWhenComputed) {
  const Trajectory reference = Straight(30);
  Trajectory estimate = reference;
  for (StampedPose& p : estimate) p.covariance = Matrix3::Identity() * 0.01;
  TrajectoryMetricsOptions options;
  options.align = true;
  options.rpe = RpeOptions{RpeDeltaUnit::kFrames, 2.0};
  const Result<TrajectoryErrorSummary> s = ComputeTrajectoryErrors(estimate, reference, options);
  ASSERT_TRUE(s.ok()) << s.message();
  const std::vector<MetricField> fields = MetricFields(*s);
  for (const char* key :
       {"align_x_m", "align_y_m", "align_yaw_deg", "nees_n", "nees_mean", "nees_in_band",
        "rpe_delta_frames", "rpe_n", "rpe_trans_rmse_m", "rpe_rot_max_deg"}) {
    EXPECT_NE(Find(fields, key), nullptr) << key;
  }
  EXPECT_EQ(Find(fields, "rpe_delta_m"), nullptr);
  EXPECT_DOUBLE_EQ(Find(fields, "rpe_n")->value, 28.0);
}

TEST(MetricFields, RelationKeysAreThoseOfEvalMd) {
  RelationErrorSummary s;
  s.n_used = 7;
  s.n_skipped = 1;
  s.trans_m = ComputeErrorStats({1.0, 3.0});
  s.rot_deg = ComputeErrorStats({2.0, 2.0});
  const std::vector<MetricField> fields = MetricFields(s);
  const std::vector<std::string> expected = {
      "rel_n",           "rel_n_skipped",    "rel_trans_mean_m",
      "rel_trans_std_m", "rel_rot_mean_deg", "rel_rot_std_deg",
      "rel_trans_max_m", "rel_rot_max_deg"};
  EXPECT_EQ(Keys(fields), expected);
  EXPECT_DOUBLE_EQ(Find(fields, "rel_trans_std_m")->value, 1.0);
  EXPECT_DOUBLE_EQ(Find(fields, "rel_n")->value, 7.0);
}

}  // namespace
}  // namespace groundline::core
