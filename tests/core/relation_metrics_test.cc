#include "groundline/core/relation_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>

#include "test_data.h"
#include "test_units.h"

namespace groundline::core {
namespace {

using ::groundline::testing::kDeg;

// 5 Hz poses on a loop, and the exact relations between consecutive poses.
Trajectory Loop(std::size_t n) {
  Trajectory trajectory;
  SE2 pose(2.0, 1.0, -0.4);
  for (std::size_t i = 0; i < n; ++i) {
    trajectory.push_back({100.0 + 0.2 * static_cast<double>(i), pose, std::nullopt});
    pose = pose * SE2::Exp(Vector3(0.3, 0.02, 0.15));
  }
  return trajectory;
}

std::vector<Relation> Consecutive(const Trajectory& reference) {
  std::vector<Relation> relations;
  for (std::size_t i = 0; i + 1 < reference.size(); ++i) {
    relations.push_back({reference[i].stamp_s, reference[i + 1].stamp_s,
                         reference[i].pose.Between(reference[i + 1].pose)});
  }
  return relations;
}

TEST(RelationMetrics, ExactEstimateHasZeroError) {
  const Trajectory reference = Loop(50);
  const Result<RelationErrorSummary> s = ComputeRelationErrors(reference, Consecutive(reference));
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(s->n_used, 49u);
  EXPECT_EQ(s->n_skipped, 0u);
  EXPECT_NEAR(s->trans_m.max, 0.0, 1e-12);
  EXPECT_NEAR(s->rot_deg.max, 0.0, 1e-9);
}

TEST(RelationMetrics, OnePerturbedPoseGivesKnownStatistics) {
  const Trajectory reference = Loop(21);  // 20 relations
  const std::vector<Relation> relations = Consecutive(reference);
  const double n = static_cast<double>(relations.size());

  // Pose 10 shifted 0.1 m in its own frame: relations 9-10 and 10-11 are off by
  // exactly 0.1 m (a rotation keeps the norm), the others are exact.
  Trajectory shifted = reference;
  shifted[10].pose = shifted[10].pose * SE2(0.06, -0.08, 0.0);
  const Result<RelationErrorSummary> t = ComputeRelationErrors(shifted, relations);
  ASSERT_TRUE(t.ok()) << t.message();
  EXPECT_EQ(t->n_used, 20u);
  EXPECT_NEAR(t->trans_m.mean, 0.2 / n, 1e-12);
  // Population std: sqrt(E[x^2] - E[x]^2).
  EXPECT_NEAR(t->trans_m.std_dev, std::sqrt(0.02 / n - (0.2 / n) * (0.2 / n)), 1e-12);
  EXPECT_NEAR(t->trans_m.max, 0.1, 1e-12);
  EXPECT_NEAR(t->rot_deg.max, 0.0, 1e-9);

  // Pose 10 turned by 3 degrees: both relations touching it are off by 3 degrees.
  Trajectory turned = reference;
  turned[10].pose = turned[10].pose * SE2(0.0, 0.0, 3.0 * kDeg);
  const Result<RelationErrorSummary> r = ComputeRelationErrors(turned, relations);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_NEAR(r->rot_deg.mean, 6.0 / n, 1e-9);
  EXPECT_NEAR(r->rot_deg.std_dev, std::sqrt(18.0 / n - (6.0 / n) * (6.0 / n)), 1e-9);
  EXPECT_NEAR(r->rot_deg.max, 3.0, 1e-9);
}

TEST(RelationMetrics, ErrorIsTheReferenceInverseTimesTheEstimate) {
  // One hand-computed relation: reference 1 m straight ahead, estimate
  // 1 m ahead and 0.1 m left, turned by 0.2 rad: E = delta_ref^-1 delta_est.
  const Trajectory estimate = {{0.0, SE2(0, 0, 0), {}}, {1.0, SE2(1.0, 0.1, 0.2), {}}};
  const std::vector<Relation> relations = {{0.0, 1.0, SE2(1.0, 0.0, 0.0)}};
  const Result<std::vector<RelationError>> e = ComputeRelationErrorList(estimate, relations, {});
  ASSERT_TRUE(e.ok());
  ASSERT_EQ(e->size(), 1u);
  EXPECT_NEAR((*e)[0].trans_m, 0.1, 1e-12);
  EXPECT_NEAR((*e)[0].rot_rad, 0.2, 1e-12);
}

TEST(RelationMetrics, UsesTheNearestPoseAndSkipsRelationsWithoutOne) {
  const Trajectory reference = Loop(30);
  std::vector<Relation> relations = Consecutive(reference);
  for (Relation& r : relations) {  // stamps 4 ms off: still the same scans
    r.t1_s += 0.004;
    r.t2_s -= 0.004;
  }
  relations.push_back({50.0, 100.2, SE2()});   // starts before the estimate
  relations.push_back({100.3, 100.4, SE2()});  // t1 is 100 ms from any pose
  const Result<RelationErrorSummary> s = ComputeRelationErrors(reference, relations);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(s->n_used, 29u);
  EXPECT_EQ(s->n_skipped, 2u);
  EXPECT_NEAR(s->trans_m.max, 0.0, 1e-12);
}

TEST(RelationMetrics, BadInputsGiveErrors) {
  const Trajectory reference = Loop(10);
  EXPECT_FALSE(ComputeRelationErrors(reference, {}).ok());
  EXPECT_FALSE(ComputeRelationErrors({}, Consecutive(reference)).ok());
  const std::vector<Relation> elsewhere = {{5000.0, 5001.0, SE2()}};
  const Result<RelationErrorSummary> none = ComputeRelationErrors(reference, elsewhere);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.message().find("5000.0"), std::string::npos) << none.message();
  RelationMetricsOptions options;
  options.max_dt_s = std::nan("");
  EXPECT_FALSE(ComputeRelationErrors(reference, Consecutive(reference), options).ok());
}

}  // namespace
}  // namespace groundline::core
