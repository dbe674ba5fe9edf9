// The BEV uncertainty map (calibration/bev_uncertainty.h): each cell's mount
// part against Monte Carlo over mounts drawn from the covariance, the
// intrinsics' part against central differences of the back-projection, the
// file's round trip, and its reader's errors.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <fstream>
#include <random>

#include "commissioning_fixture.h"
#include "groundline/calibration/bev_uncertainty.h"
#include "groundline/calibration/calibration_report.h"
#include "groundline/calibration/floor_calibration.h"
#include "groundline/calibration/floor_projection.h"
#include "groundline/core/atomic_file.h"
#include "test_data.h"

namespace groundline::calibration {
namespace {

using ::groundline::testing::CommissioningSceneOrFail;

CameraMount Perturbed(const CameraMount& m, const Eigen::Matrix<double, 6, 1>& d) {
  CameraMount p = m;
  p.height_m += d[0];
  p.pitch_rad += d[1];
  p.roll_rad += d[2];
  p.yaw_rad += d[3];
  p.forward_m += d[4];
  p.lateral_m += d[5];
  return p;
}

// A mount covariance of a plausible commissioning: 1 mm height, 0.05 deg of
// pitch, roll and yaw, 1 mm forward and lateral, with a pitch-height
// correlation as the tag solve has.
FloorExtrinsicsResult Solution(const CameraMount& mount) {
  FloorExtrinsicsResult s;
  s.mount = mount;
  const double deg = std::numbers::pi / 180.0;
  Eigen::Matrix<double, 6, 1> sd;
  sd << 1e-3, 0.05 * deg, 0.05 * deg, 0.05 * deg, 1e-3, 1e-3;
  s.covariance = Eigen::Matrix<double, 6, 6>(sd.cwiseAbs2().asDiagonal());
  s.covariance(0, 1) = s.covariance(1, 0) = 0.6 * sd[0] * sd[1];
  return s;
}

TEST(BevUncertaintyMap, MountPartOfEachCellMatchesMonteCarloOverTheMountCovariance) {
  const sim::CommissioningScene scene = CommissioningSceneOrFail(sim::CommissioningOptions{});
  const FloorExtrinsicsResult solution = Solution(scene.true_mount);
  const BevUncertaintyMap map =
      ComputeBevUncertaintyMap(scene.camera, solution, nullptr).value();
  ASSERT_EQ(map.cells_x, 20);
  ASSERT_EQ(map.cells_y, 20);
  EXPECT_FALSE(map.includes_intrinsics);
  EXPECT_EQ(map.camera_fingerprint, CameraFingerprint(scene.camera));
  EXPECT_GT(map.KnownCells(), 20);
  EXPECT_LT(map.KnownCells(), 400);  // the camera does not see behind itself

  const FloorProjection nominal(scene.camera, solution.mount);
  const Eigen::Matrix<double, 6, 6> L = solution.covariance.llt().matrixL();
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n01;
  int checked = 0;
  for (int iy = 0; iy < map.cells_y; iy += 3) {
    for (int ix = 0; ix < map.cells_x; ix += 3) {
      const Eigen::Vector2d p = map.CellCentre(ix, iy);
      const std::optional<Eigen::Matrix2d> cov = map.CovarianceAt(p);
      const core::Result<Eigen::Vector2d> q = nominal.PixelOfFloorPoint(p);
      const bool seen = q.ok() && scene.camera.InImage(*q);
      EXPECT_EQ(cov.has_value(), seen) << p.transpose();
      if (!cov) continue;
      // The pixel that sees p, back-projected through mounts drawn from the covariance.
      Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
      constexpr int kDraws = 3000;
      for (int k = 0; k < kDraws; ++k) {
        Eigen::Matrix<double, 6, 1> z;
        for (int i = 0; i < 6; ++i) z[i] = n01(rng);
        const FloorProjection drawn(scene.camera, Perturbed(solution.mount, L * z));
        const Eigen::Vector2d e = drawn.FloorPointOfPixel(*q).value() - p;
        sum += e * e.transpose();
      }
      const Eigen::Matrix2d empirical = sum / kDraws;
      // 3000 draws: the trace to ~3 %; 10 % allows for the linearization.
      EXPECT_NEAR(cov->trace(), empirical.trace(), 0.1 * empirical.trace()) << p.transpose();
      EXPECT_NEAR((*cov - empirical).norm(), 0.0, 0.15 * empirical.norm()) << p.transpose();
      ++checked;
    }
  }
  EXPECT_GE(checked, 5);
  // Farther ahead the same mount error moves the floor point more.
  const double near = map.CovarianceAt({1.0, 0.0}).value().trace();
  const double far = map.CovarianceAt({2.0, 0.0}).value().trace();
  EXPECT_GT(far, 2.0 * near);
}

TEST(BevUncertaintyMap, IntrinsicsPartIsTheBackProjectionOfVarQ) {
  const sim::CommissioningScene scene = CommissioningSceneOrFail(sim::CommissioningOptions{});
  const FloorExtrinsicsResult solution = Solution(scene.true_mount);
  IntrinsicsReportSummary intrinsics;
  constexpr double kSigmaPx = 0.4;
  for (const double range : {0.5, 10.0}) {
    IntrinsicsReportSummary::CovarianceMap m;
    m.range_m = range;
    m.cells_x = 16;
    m.cells_y = 12;
    m.covariance_px2.assign(16 * 12, kSigmaPx * kSigmaPx * Eigen::Matrix2d::Identity());
    // The top-left cell of the imager is not known: its floor cells drop out.
    m.covariance_px2[0] = Eigen::Matrix2d::Constant(std::nan(""));
    intrinsics.covariance_maps.push_back(m);
  }
  const BevUncertaintyMap mount_only =
      ComputeBevUncertaintyMap(scene.camera, solution, nullptr).value();
  const BevUncertaintyMap both =
      ComputeBevUncertaintyMap(scene.camera, solution, &intrinsics).value();
  EXPECT_TRUE(both.includes_intrinsics);
  const FloorProjection floor(scene.camera, solution.mount);
  int checked = 0, dropped = 0;
  for (int iy = 0; iy < both.cells_y; ++iy) {
    for (int ix = 0; ix < both.cells_x; ++ix) {
      const Eigen::Vector2d p = both.CellCentre(ix, iy);
      const std::optional<Eigen::Matrix2d> a = mount_only.CovarianceAt(p);
      const std::optional<Eigen::Matrix2d> b = both.CovarianceAt(p);
      if (!a) {
        EXPECT_FALSE(b.has_value());
        continue;
      }
      const Eigen::Vector2d q = floor.PixelOfFloorPoint(p).value();
      // The report's cell holding q (the lookup's rule: cell = floor((q + 0.5) / size * cells)).
      if ((q.x() + 0.5) / 1280.0 * 16 < 1.0 && (q.y() + 0.5) / 1024.0 * 12 < 1.0) {
        EXPECT_FALSE(b.has_value()) << "seen in the unknown imager cell " << q.transpose();
        ++dropped;
        continue;
      }
      ASSERT_TRUE(b.has_value()) << p.transpose();
      Eigen::Matrix2d J;
      for (int c = 0; c < 2; ++c) {
        Eigen::Vector2d step = Eigen::Vector2d::Zero();
        step[c] = 0.5;
        J.col(c) = floor.FloorPointOfPixel(q + step).value() - floor.FloorPointOfPixel(q - step).value();
      }
      const Eigen::Matrix2d expected = kSigmaPx * kSigmaPx * J * J.transpose();
      EXPECT_NEAR((*b - *a - expected).norm(), 0.0, 0.01 * expected.norm()) << p.transpose();
      ++checked;
    }
  }
  EXPECT_GT(checked, 20);
  std::printf("cells checked %d, dropped as unknown in the imager %d; worst %.2f mm (mount only "
              "%.2f mm)\n",
              checked, dropped, both.WorstRmsMm(), mount_only.WorstRmsMm());
}

TEST(BevUncertaintyMap, FileRoundTripsAndTheReaderNamesWhatIsWrong) {
  const sim::CommissioningScene scene = CommissioningSceneOrFail(sim::CommissioningOptions::Small());
  const BevUncertaintyMap map =
      ComputeBevUncertaintyMap(scene.camera, Solution(scene.true_mount), nullptr).value();
  const std::filesystem::path dir = groundline::testing::ScratchDir("bev_uncertainty_io");
  ASSERT_TRUE(core::WriteFileAtomically(dir / "map.json", BevUncertaintyJson(map)).ok());
  const core::Result<BevUncertaintyMap> back = ReadBevUncertaintyMap(dir / "map.json");
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(back->cells_x, map.cells_x);
  EXPECT_EQ(back->cells_y, map.cells_y);
  EXPECT_EQ(back->camera_fingerprint, map.camera_fingerprint);
  ASSERT_EQ(back->covariance_m2.size(), map.covariance_m2.size());
  for (std::size_t i = 0; i < map.covariance_m2.size(); ++i) {
    if (!map.covariance_m2[i].allFinite()) {
      EXPECT_FALSE(back->covariance_m2[i].allFinite());
      continue;
    }
    EXPECT_NEAR((back->covariance_m2[i] - map.covariance_m2[i]).norm(), 0.0,
                1e-12 * map.covariance_m2[i].norm());
  }
  EXPECT_TRUE(CheckBevUncertaintyCamera(*back, scene.camera, "map.json").ok());
  const sim::CommissioningScene other = CommissioningSceneOrFail(sim::CommissioningOptions{});
  const core::Status mismatch = CheckBevUncertaintyCamera(*back, other.camera, "map.json");
  EXPECT_FALSE(mismatch.ok());
  EXPECT_NE(mismatch.message().find("another camera"), std::string::npos) << mismatch.message();

  const auto error_of = [&](const std::string& text) {
    std::ofstream(dir / "bad.json") << text;
    const core::Result<BevUncertaintyMap> r = ReadBevUncertaintyMap(dir / "bad.json");
    return r.ok() ? std::string("(accepted)") : r.message();
  };
  const std::string head =
      R"({"format": "groundline.bev_uncertainty", "version": 1, "frame": "base_link",
          "camera_fingerprint": "x", "includes_intrinsics": false, "x0_m": 0, "y0_m": -1,
          "cell_m": 0.5, "cells_x": 2, "cells_y": 1, )";
  EXPECT_EQ(error_of(head + R"("covariance_m2": [[1e-6, 0, 1e-6], null]})"), "(accepted)");
  EXPECT_NE(error_of(head + R"("covariance_m2": [[1e-6, 0, 1e-6]]})").find("covariance_m2"),
            std::string::npos);
  EXPECT_NE(error_of(head + R"("covariance_m2": [[1e-6, 2e-6, 1e-6], null]})")
                .find("covariance_m2[0]"),
            std::string::npos);
  EXPECT_NE(error_of(head + R"("covariance_m2": [null, null]})").find("at least one known"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"format": "something else"})").find("format"), std::string::npos);
  std::string no_cell = head;
  no_cell.replace(no_cell.find("\"cell_m\": 0.5"), 13, "\"cell_m\": 0");
  EXPECT_NE(error_of(no_cell + R"("covariance_m2": [null, null]})").find("cell_m"),
            std::string::npos);
  EXPECT_NE(error_of("[1, 2").find("not valid JSON"), std::string::npos);
  EXPECT_NE(error_of("{}").find("format"), std::string::npos);
  // Where a point falls: the cell holding it, nothing outside the grid.
  std::ofstream(dir / "two.json") << head + R"("covariance_m2": [[1e-6, 0, 2e-6], [3e-6, 0, 4e-6]]})";
  const BevUncertaintyMap small = ReadBevUncertaintyMap(dir / "two.json").value();
  EXPECT_DOUBLE_EQ(small.CovarianceAt({0.25, -0.9}).value()(1, 1), 2e-6);
  EXPECT_DOUBLE_EQ(small.CovarianceAt({0.75, -0.6}).value()(1, 1), 4e-6);
  EXPECT_FALSE(small.CovarianceAt({1.01, -0.9}).has_value());
  EXPECT_FALSE(small.CovarianceAt({0.25, -0.4}).has_value());
  EXPECT_FALSE(small.CovarianceAt({-0.01, -0.9}).has_value());
}

TEST(BevUncertaintyMap, GridOptionsAreChecked) {
  BevUncertaintyGridOptions g;
  EXPECT_TRUE(g.Validate().ok());
  g.cell_m = 0.0;
  EXPECT_NE(g.Validate().message().find("cell_m"), std::string::npos);
  g = {};
  g.x_max_m = g.x_min_m;
  EXPECT_FALSE(g.Validate().ok());
  g = {};
  g.cell_m = 0.01;
  g.x_max_m = 100.0;
  EXPECT_NE(g.Validate().message().find("at most"), std::string::npos);
}

}  // namespace
}  // namespace groundline::calibration
