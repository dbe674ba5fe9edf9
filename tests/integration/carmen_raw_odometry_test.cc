// The Kuemmerle et al. 2009 relation metric on real logs, end to end through
// the CARMEN reader, the raw-odometry trajectory and the relation metric:
// it must reproduce the raw-odometry figures published with the shared data
// (../shared/data/README.md) within 1 %.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "groundline/core/relation_metrics.h"
#include "groundline/io/carmen.h"
#include "groundline/io/carmen_trajectory.h"
#include "groundline/io/relations.h"
#include "test_data.h"

namespace groundline {
namespace {

struct PublishedRawOdometry {
  std::string log;
  std::string relations;
  std::size_t n_relations;
  double trans_mean_m, trans_std_m, rot_mean_deg, rot_std_deg;
};

class CarmenRawOdometry : public ::testing::TestWithParam<PublishedRawOdometry> {};

// Relative difference, for figures published to 3-4 significant digits.
double RelativeError(double measured, double published) {
  return std::abs(measured - published) / std::abs(published);
}

TEST_P(CarmenRawOdometry, ReproducesPublishedRelationErrorWithinOnePercent) {
  const PublishedRawOdometry& p = GetParam();
  GROUNDLINE_REQUIRE_DATA("lidar2d/" + p.log);
  GROUNDLINE_REQUIRE_DATA("lidar2d/" + p.relations);
  const auto dir = ::groundline::testing::SharedDataDir() / "lidar2d";

  core::Result<io::CarmenLog> log = io::ReadCarmenLog(dir / p.log);
  ASSERT_TRUE(log.ok()) << log.message();
  core::Result<core::Trajectory> odometry = io::CarmenScanTrajectory(*log);
  ASSERT_TRUE(odometry.ok()) << odometry.message();
  core::Result<std::vector<core::Relation>> relations = io::ReadRelations(dir / p.relations);
  ASSERT_TRUE(relations.ok()) << relations.message();
  ASSERT_EQ(relations->size(), p.n_relations);

  core::Result<core::RelationErrorSummary> errors =
      core::ComputeRelationErrors(*odometry, *relations);
  ASSERT_TRUE(errors.ok()) << errors.message();
  EXPECT_EQ(errors->n_used, p.n_relations);
  EXPECT_EQ(errors->n_skipped, 0u);
  EXPECT_LT(RelativeError(errors->trans_m.mean, p.trans_mean_m), 0.01) << errors->trans_m.mean;
  EXPECT_LT(RelativeError(errors->trans_m.std_dev, p.trans_std_m), 0.01) << errors->trans_m.std_dev;
  EXPECT_LT(RelativeError(errors->rot_deg.mean, p.rot_mean_deg), 0.01) << errors->rot_deg.mean;
  EXPECT_LT(RelativeError(errors->rot_deg.std_dev, p.rot_std_deg), 0.01) << errors->rot_deg.std_dev;
}

INSTANTIATE_TEST_SUITE_P(SharedLogs, CarmenRawOdometry,
                         ::testing::Values(PublishedRawOdometry{"aces.clf.bz2", "aces.relations",
                                                                1279, 0.549, 2.674, 2.33, 6.50},
                                           PublishedRawOdometry{"mit-csail.clf.bz2",
                                                                "mit-csail.relations", 1172, 1.682,
                                                                5.292, 5.07, 8.24}),
                         [](const ::testing::TestParamInfo<PublishedRawOdometry>& info) {
                           return info.index == 0 ? std::string("Aces") : std::string("MitCsail");
                         });

}  // namespace
}  // namespace groundline
