// ViewCoverage on views projected through a known pinhole camera, and
// BoardSharpness on rendered chessboard corners.
#include "groundline/calibration/view_coverage.h"
#include "test_units.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>

namespace groundline::calibration {
namespace {

constexpr int kWidth = 640, kHeight = 480;
constexpr double kHfovDeg = 60.0;
using ::groundline::testing::kDeg;

CalibTarget Chessboard() {
  CalibTarget t;
  t.name = "chessboard_9x6_25mm";
  t.type = TargetType::kChessboard;
  t.inner_corners_x = 9;
  t.inner_corners_y = 6;
  t.square_m = 0.025;
  return t;
}

double Focal() { return 0.5 * kWidth / std::tan(0.5 * kHfovDeg * kDeg); }

// The board centred on pixel (u, v) at `distance_m`, its normal turned by
// the two tilts; the pinhole is the one ViewCoverage guesses (exact poses).
BoardObservation ViewAt(const BoardGrid& grid, double u, double v, double distance_m,
                        double tilt_vertical_deg, double tilt_horizontal_deg) {
  const double f = Focal(), cx = 0.5 * (kWidth - 1), cy = 0.5 * (kHeight - 1);
  const Eigen::Matrix3d R =
      (Eigen::AngleAxisd(tilt_vertical_deg * kDeg, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(-tilt_horizontal_deg * kDeg, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  Eigen::Vector3d centre_board = Eigen::Vector3d::Zero();
  for (int i : grid.observable) centre_board += grid.Point_board(i);
  centre_board /= static_cast<double>(grid.observable.size());
  const Eigen::Vector3d centre_cam =
      distance_m * Eigen::Vector3d((u - cx) / f, (v - cy) / f, 1.0).normalized();
  const Eigen::Vector3d t = centre_cam - R * centre_board;
  BoardObservation obs;
  for (int i : grid.observable) {
    const Eigen::Vector3d p = R * grid.Point_board(i) + t;
    obs.grid_index.push_back(i);
    obs.corners_px.emplace_back(f * p.x() / p.z() + cx, f * p.y() / p.z() + cy);
  }
  return obs;
}

TEST(RoughBoardPose, RecoversTiltsAndDistanceWithTheGuessedPinhole) {
  const BoardGrid grid = MakeBoardGrid(Chessboard());
  for (const auto& [vertical, horizontal] : {std::pair{30.0, 0.0}, std::pair{0.0, -25.0}}) {
    core::Result<RoughBoardPose> pose = EstimateRoughBoardPose(
        ViewAt(grid, 300, 260, 0.5, vertical, horizontal), grid, kWidth, kHeight, kHfovDeg);
    ASSERT_TRUE(pose.ok()) << pose.message();
    EXPECT_NEAR(pose->tilt_about_vertical_deg, vertical, 0.1);
    EXPECT_NEAR(pose->tilt_about_horizontal_deg, horizontal, 0.1);
    EXPECT_NEAR(pose->distance_m, 0.5, 1e-3);
  }
  const RoughBoardPose flat =
      *EstimateRoughBoardPose(ViewAt(grid, 320, 240, 0.8, 0, 0), grid, kWidth, kHeight, kHfovDeg);
  EXPECT_NEAR(flat.tilt_about_vertical_deg, 0.0, 0.1);
  EXPECT_NEAR(flat.tilt_about_horizontal_deg, 0.0, 0.1);
  EXPECT_NEAR(flat.distance_m, 0.8, 1e-3);
}

TEST(ViewCoverage, FirstViewIsKeptAndTheGuidanceNamesWhatIsMissing) {
  const BoardGrid grid = MakeBoardGrid(Chessboard());
  ViewCoverage coverage(grid, kWidth, kHeight, ViewCoverageOptions());
  const ViewVerdict first = coverage.Consider(ViewAt(grid, 320, 240, 0.5, 0, 0), 0.5);
  EXPECT_EQ(first.decision, ViewDecision::kKept) << first.reason;
  EXPECT_EQ(coverage.views(), 1);
  EXPECT_FALSE(coverage.Complete());
  const std::vector<std::string> missing = coverage.Missing();
  const auto has = [&](const std::string& text) {
    for (const std::string& m : missing) {
      if (m.find(text) != std::string::npos) return true;
    }
    return false;
  };
  EXPECT_TRUE(
      has("hold the board in the image's top-left (0 of 10 corners), top (0 of 10 "
          "corners), top-right (0 of 10 corners), left ("));
  EXPECT_TRUE(has("bottom-right (0 of 10 corners)"));
  EXPECT_FALSE(has("centre"));  // a 220 px board in the middle covers it
  EXPECT_TRUE(has("tilt the board about its vertical axis"));
  EXPECT_TRUE(has("tilt the board about its horizontal axis"));
  EXPECT_TRUE(has("vary the distance"));
  EXPECT_TRUE(has("11 more view(s) needed"));
  EXPECT_NE(coverage.StatusLine().find("1 of 12 views"), std::string::npos)
      << coverage.StatusLine();
}

TEST(ViewCoverage, RejectsNearDuplicatesBlurAndViewsThatAddNothing) {
  const BoardGrid grid = MakeBoardGrid(Chessboard());
  ViewCoverageOptions options;
  options.novelty_cells_x = options.novelty_cells_y = 1;  // only tilt and distance are new
  ViewCoverage coverage(grid, kWidth, kHeight, options);
  ASSERT_EQ(coverage.Consider(ViewAt(grid, 320, 240, 0.5, 0, 0), 0.5).decision,
            ViewDecision::kKept);
  const ViewVerdict duplicate = coverage.Consider(ViewAt(grid, 324, 242, 0.5, 0, 0), 0.5);
  EXPECT_EQ(duplicate.decision, ViewDecision::kDuplicate) << duplicate.reason;
  EXPECT_NE(duplicate.reason.find("near-duplicate of view 1"), std::string::npos);
  // 80 px away: not a duplicate, but the same tilt and distance bins.
  const ViewVerdict same = coverage.Consider(ViewAt(grid, 400, 240, 0.5, 0, 0), 0.5);
  EXPECT_EQ(same.decision, ViewDecision::kNothingNew) << same.reason;
  ASSERT_EQ(coverage.Consider(ViewAt(grid, 320, 240, 0.5, 30, 0), 0.5).decision,
            ViewDecision::kKept);
  ASSERT_EQ(coverage.Consider(ViewAt(grid, 320, 240, 0.5, 0, 30), 0.5).decision,
            ViewDecision::kKept);
  const ViewVerdict blurred = coverage.Consider(ViewAt(grid, 320, 240, 0.7, -30, 0), 0.2);
  EXPECT_EQ(blurred.decision, ViewDecision::kBlurred) << blurred.reason;
  EXPECT_EQ(coverage.Consider(ViewAt(grid, 320, 240, 0.7, -30, 0), 0.45).decision,
            ViewDecision::kKept);
  EXPECT_EQ(coverage.views(), 4);
}

TEST(ViewCoverage, PlannedSessionOverEveryRegionWithTiltsAndDistancesCompletes) {
  const BoardGrid grid = MakeBoardGrid(Chessboard());
  ViewCoverage coverage(grid, kWidth, kHeight, ViewCoverageOptions());
  int step = 0;
  for (double v : {80.0, 240.0, 400.0}) {
    for (double u : {110.0, 320.0, 530.0}) {
      const double tilt = (step % 2 == 0 ? 1 : -1) * 30.0;
      const ViewVerdict verdict =
          coverage.Consider(ViewAt(grid, u, v, step % 3 == 0 ? 0.45 : 0.65, step % 4 < 2 ? tilt : 0,
                                   step % 4 < 2 ? 0 : tilt),
                            0.5);
      EXPECT_EQ(verdict.decision, ViewDecision::kKept) << verdict.reason;
      ++step;
    }
  }
  EXPECT_FALSE(coverage.Complete());  // 9 views of 12
  for (int i = 0; i < 3; ++i) {
    const ViewVerdict verdict =
        coverage.Consider(ViewAt(grid, 220 + 100 * i, 240, 0.5 + 0.3 * i, 0, 15), 0.5);
    EXPECT_EQ(verdict.decision, ViewDecision::kKept) << verdict.reason;
  }
  EXPECT_EQ(coverage.views(), 12);
  for (int r = 0; r < 9; ++r) EXPECT_GE(coverage.region_corners()[r], 10) << "region " << r;
  // Regions, tilts and distances are there, but no corner reached the
  // image's outer ring yet (what the report's border rule needs).
  ASSERT_FALSE(coverage.Complete());
  ASSERT_EQ(coverage.Missing().size(), 1u);
  EXPECT_EQ(coverage.Missing()[0].rfind(
                "push the board's corners to within 10% of the image's top-left corner (", 0),
            0u)
      << coverage.Missing()[0];
  // One view into each zone, each with a tilt bin of its own (so that it is new).
  const double tilt_v[8] = {-12, -22, 12, 22, -12, -22, 12, 22};
  int k = 0;
  for (double v : {62.0, 240.0, 418.0}) {
    for (double u : {90.0, 320.0, 550.0}) {
      if (u == 320.0 && v == 240.0) continue;
      const ViewVerdict verdict =
          coverage.Consider(ViewAt(grid, u, v, 0.65, tilt_v[k], k < 4 ? 8 : -8), 0.5);
      EXPECT_EQ(verdict.decision, ViewDecision::kKept) << verdict.reason;
      ++k;
    }
  }
  EXPECT_EQ(coverage.views(), 20);
  EXPECT_TRUE(coverage.Complete()) << coverage.StatusLine() << " " << coverage.Missing()[0];
  EXPECT_NE(coverage.StatusLine().find("coverage complete"), std::string::npos);
}

// A 640x480 chessboard of 40 px squares, optionally blurred.
cv::Mat Chessboard640(double blur_sigma_px, BoardObservation* corners) {
  cv::Mat image(480, 640, CV_8UC1);
  for (int v = 0; v < 480; ++v) {
    for (int u = 0; u < 640; ++u) image.at<std::uint8_t>(v, u) = ((u / 40 + v / 40) % 2) ? 220 : 30;
  }
  if (blur_sigma_px > 0) cv::GaussianBlur(image, image, cv::Size(0, 0), blur_sigma_px);
  for (int j = 1; j < 12; ++j) {
    for (int i = 1; i < 16; ++i) {
      corners->grid_index.push_back(static_cast<int>(corners->corners_px.size()));
      corners->corners_px.emplace_back(40 * i - 0.5, 40 * j - 0.5);
    }
  }
  return image;
}

TEST(BoardSharpness, FallsAsTheImageIsBlurred) {
  BoardObservation corners;
  const double sharp = BoardSharpness(Chessboard640(0.0, &corners), corners);
  BoardObservation c2, c3;
  const double sigma1 = BoardSharpness(Chessboard640(1.0, &c2), c2);
  const double sigma3 = BoardSharpness(Chessboard640(3.0, &c3), c3);
  EXPECT_NEAR(sharp, 0.5, 0.1);
  EXPECT_NEAR(sigma3, 0.4 / 3.0, 0.04);
  EXPECT_GT(sharp, sigma1);
  EXPECT_GT(sigma1, sigma3);
  EXPECT_LT(sigma3, 0.5 * sharp);  // a blur of 3 px is rejected by the default ratio
}

}  // namespace
}  // namespace groundline::calibration
