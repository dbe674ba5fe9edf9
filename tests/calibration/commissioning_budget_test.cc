// The BEV error budget of a commissioning report end to end: an intrinsic
// calibration of the simulated commissioning camera (1280 x 1024) from
// synthetic board views, its report.json read back as the floor calibration
// reads it, the floor mount solved with the calibrated camera, and the
// intrinsics' uncertainty carried to the floor 1, 2 and 4 m ahead.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <random>

#include "groundline/calibration/calibration_report.h"
#include "groundline/calibration/floor_calibration.h"
#include "groundline/core/random_draws.h"
#include "groundline/sim/commissioning_scene.h"
#include "synthetic_views.h"
#include "test_data.h"

namespace groundline::calibration {
namespace {

// Tag corners of every vehicle pose, projected through the TRUE camera and
// mount with 0.3 px noise (the floor images' corners).
std::vector<FloorImage> FloorCorners(const sim::CommissioningScene& scene, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.3);
  std::vector<FloorImage> images;
  for (const VehiclePose& pose : scene.layout.vehicle_poses) {
    FloorImage im{pose.image, pose.T_floor_base, {}};
    for (const SurveyedTag& tag : scene.layout.tags) {
      const auto corners = tag.CornersInFrame();
      std::vector<FloorCorner> seen;
      for (int c = 0; c < 4; ++c) {
        const core::Result<Eigen::Vector2d> px =
            PredictFloorPixel(scene.camera, scene.true_mount, pose.T_floor_base, corners[c]);
        if (!px.ok() || !scene.camera.InImage(*px)) break;
        seen.push_back({tag.id, c, corners[c], *px + core::DrawVector<2>(noise, rng)});
      }
      if (seen.size() == 4) im.corners.insert(im.corners.end(), seen.begin(), seen.end());
    }
    images.push_back(std::move(im));
  }
  return images;
}

TEST(CommissioningBudget, IntrinsicsUncertaintyReachesTheFloorOfTheSimulatedVehicle) {
  const sim::CommissioningScene scene =
      sim::MakeCommissioningScene(sim::CommissioningOptions{}).value();
  ASSERT_EQ(scene.camera.width_px(), 1280);
  const CalibTarget target = testing::SyntheticAprilGrid();
  const BoardGrid grid = MakeBoardGrid(target);
  const std::vector<CalibrationView> views = testing::SyntheticViews(
      scene.camera, target, grid, 24, 0.2, 11, /*top_left_only=*/false, /*reach_borders=*/true);
  ASSERT_EQ(views.size(), 24u);
  IntrinsicCalibrationOptions options;
  options.lens_model = scene.camera.lens_model();
  core::Result<IntrinsicCalibration> cal = CalibrateIntrinsics(views, grid, 1280, 1024, options);
  ASSERT_TRUE(cal.ok()) << cal.message();
  const CalibrationReport report = BuildCalibrationReport(*cal, "grid", {}, ReportThresholds{});
  const std::filesystem::path dir = groundline::testing::ScratchDir("commissioning_budget");
  ASSERT_TRUE(WriteCalibrationOutputs(dir, report, *cal).ok());
  const core::Result<IntrinsicsReportSummary> summary =
      ReadIntrinsicsReportSummary(dir / "report.json");
  ASSERT_TRUE(summary.ok()) << summary.message();
  ASSERT_EQ(summary->covariance_maps.size(), 3u);
  EXPECT_TRUE(CheckSameCamera(*summary, cal->camera, "camera.cameramodel").ok());

  FloorCalibration floor;
  floor.images = FloorCorners(scene, 5);
  floor.solution = SolveFloorExtrinsics(cal->camera, floor.images, {}).value();
  for (int i = 0; i < 3; ++i) {
    floor.bev[i] =
        BevErrorAhead(floor.solution.mount, floor.solution.covariance, i == 2 ? 4.0 : i + 1.0)
            .value();
  }
  AddIntrinsicsToBev(cal->camera, *summary, &floor);
  ASSERT_EQ(floor.bev_budget.size(), 3u);
  int known = 0;
  for (const BevErrorBudget& b : floor.bev_budget) {
    if (!b.known) {
      std::printf("BEV %.0f m ahead: not in the image\n", b.distance_m);
      continue;
    }
    ++known;
    std::printf(
        "BEV %.0f m ahead: pixel %.0f,%.0f, range %.2f m: mount %.3f mm, intrinsics %.3f "
        "mm, both %.3f mm (3 sigma %.3f mm)\n",
        b.distance_m, b.pixel.x(), b.pixel.y(), b.range_m, b.extrinsics_rms_mm, b.intrinsics_rms_mm,
        b.total_rms_mm, b.total_sigma3_mm);
    EXPECT_GT(b.intrinsics_rms_mm, 0.0);
    EXPECT_GE(b.total_rms_mm, b.extrinsics_rms_mm);
    EXPECT_GE(b.total_rms_mm, b.intrinsics_rms_mm);
  }
  EXPECT_GE(known, 2);  // 1 and 2 m ahead are seen by the commissioning camera
  // The map over the BEV: every cell the camera sees with its intrinsics'
  // part, never less than the mount's part alone.
  const BevUncertaintyMap mount_only =
      ComputeBevUncertaintyMap(cal->camera, floor.solution, nullptr).value();
  ASSERT_TRUE(floor.bev_map.includes_intrinsics);
  EXPECT_GT(floor.bev_map.KnownCells(), 20);
  EXPECT_LE(floor.bev_map.KnownCells(), mount_only.KnownCells());
  for (std::size_t i = 0; i < mount_only.covariance_m2.size(); ++i) {
    const Eigen::Matrix2d& both = floor.bev_map.covariance_m2[i];
    if (!both.allFinite()) continue;
    const Eigen::Matrix2d extra = both - mount_only.covariance_m2[i];
    EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(extra).eigenvalues().minCoeff(),
              -1e-15);
  }
  std::printf("BEV uncertainty map: %d cells seen, worst %.2f mm (mount only %.2f mm)\n",
              floor.bev_map.KnownCells(), floor.bev_map.WorstRmsMm(), mount_only.WorstRmsMm());
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(0.9, 0.0), Eigen::Vector2d(1.5, 0.5),
                                   Eigen::Vector2d(1.5, -0.5), Eigen::Vector2d(1.9, 0.0)}) {
    const std::optional<Eigen::Matrix2d> c = floor.bev_map.CovarianceAt(p);
    if (c)
      std::printf("  cell at (%.1f, %.1f) m: %.2f mm\n", p.x(), p.y(), 1e3 * std::sqrt(c->trace()));
  }
  // Farther ahead, the same pixel error covers more floor.
  if (floor.bev_budget[0].known && floor.bev_budget[1].known) {
    EXPECT_GT(floor.bev_budget[1].intrinsics_rms_mm, floor.bev_budget[0].intrinsics_rms_mm);
  }
}

}  // namespace
}  // namespace groundline::calibration
