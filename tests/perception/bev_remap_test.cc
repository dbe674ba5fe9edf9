// BevRemap against independent per-point projections (FloorProjection), a
// camera image rendered here by unprojecting each pixel to the floor, and the
// pinhole warpPerspective baseline.
#include "groundline/perception/bev_remap.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "groundline/calibration/floor_projection.h"
#include "groundline/perception/hesse_line.h"
#include "test_units.h"

namespace groundline::perception {
namespace {

using calibration::CameraModel;
using calibration::CameraMount;
using calibration::FloorProjection;

using ::groundline::testing::kDeg;

// The reference camera (fx 1132 px on 1280 x 1024) with mild OPENCV8 distortion.
CameraModel ReferenceCamera(double scale = 1.0) {
  const core::Result<CameraModel> camera =
      CameraModel::Create("LENSMODEL_OPENCV8",
                          {1132.0 * scale, 1131.0 * scale, 639.5 * scale, 511.5 * scale, -0.12,
                           0.05, 0.0006, -0.0004, 0.0, 0.004, -0.002, 0.001},
                          static_cast<int>(1280 * scale), static_cast<int>(1024 * scale));
  EXPECT_TRUE(camera.ok()) << camera.message();
  return *camera;
}

TEST(BevGridTest, CellAndFloorPointAreInverse) {
  const BevGrid grid(BevGridOptions{});
  EXPECT_EQ(grid.rows(), 180);
  EXPECT_EQ(grid.cols(), 200);
  const Eigen::Vector2d corner = grid.FloorPointOfCell({-0.5, -0.5});
  EXPECT_NEAR(corner.x(), 2.4, 1e-12);
  EXPECT_NEAR(corner.y(), 1.0, 1e-12);
  const Eigen::Vector2d p(1.234, -0.567);
  const Eigen::Vector2d cell = grid.CellOfFloorPoint(p);
  EXPECT_LT((grid.FloorPointOfCell(cell) - p).norm(), 1e-12);
  const Eigen::Vector3d affine = grid.FloorFromCell() * Eigen::Vector3d(cell.x(), cell.y(), 1.0);
  EXPECT_LT((affine.head<2>() - p).norm(), 1e-12);
}

TEST(BevGridTest, ValidateNamesTheBadField) {
  BevGridOptions options;
  options.x_max_m = 0.5;
  EXPECT_NE(options.Validate().message().find("x_max_m"), std::string::npos);
  options = BevGridOptions{};
  options.cell_m = 0.0;
  EXPECT_NE(options.Validate().message().find("cell_m"), std::string::npos);
  EXPECT_TRUE(BevGridOptions{}.Validate().ok());
}

TEST(BevRemapTest, TableMatchesPerPointFloorProjection) {
  const CameraModel camera = ReferenceCamera();
  const CameraMount mount;
  const BevRemap remap(camera, mount, BevRemap::Options{});
  const FloorProjection projection(camera, mount);
  const BevGrid& grid = remap.grid();
  int valid = 0;
  for (int row = 0; row < grid.rows(); ++row) {
    for (int col = 0; col < grid.cols(); ++col) {
      const Eigen::Vector2d floor = grid.FloorPointOfCell({col, row});
      const core::Result<Eigen::Vector2d> pixel = projection.PixelOfFloorPoint(floor);
      const bool expected_valid = pixel.ok() && pixel->x() >= 0 && pixel->y() >= 0 &&
                                  pixel->x() <= 1279 && pixel->y() <= 1023;
      const bool table_valid = remap.valid_mask().at<std::uint8_t>(row, col) != 0;
      ASSERT_EQ(table_valid, expected_valid) << "cell " << col << ", " << row;
      if (!table_valid) continue;
      ++valid;
      const cv::Vec2f table = remap.pixel_map().at<cv::Vec2f>(row, col);
      ASSERT_NEAR(table[0], pixel->x(), 0.01) << "cell " << col << ", " << row;
      ASSERT_NEAR(table[1], pixel->y(), 0.01) << "cell " << col << ", " << row;
    }
  }
  EXPECT_EQ(valid, remap.valid_cells());
  // The reference camera sees the floor from about 0.67 m to 2.2 m ahead.
  auto valid_at = [&](double x, double y) {
    const Eigen::Vector2d cell = grid.CellOfFloorPoint({x, y});
    return remap.valid_mask().at<std::uint8_t>(static_cast<int>(std::lround(cell.y())),
                                               static_cast<int>(std::lround(cell.x()))) != 0;
  };
  EXPECT_TRUE(valid_at(0.75, 0.0));
  EXPECT_TRUE(valid_at(2.1, 0.0));
  EXPECT_TRUE(valid_at(2.1, 0.8));
  EXPECT_FALSE(valid_at(0.62, 0.0));
  EXPECT_FALSE(valid_at(2.35, 0.0));
  EXPECT_FALSE(valid_at(0.75, 0.6));
}

// Sub-cell centre of the bright ridge along one BEV row (scan_rows = false) or
// column (true): background-subtracted centroid within +-6 cells of the maximum.
bool RidgeCentre(const cv::Mat& bev, const cv::Mat& mask, int index, bool along_rows,
                 double background, double* centre) {
  const int n = along_rows ? bev.rows : bev.cols;
  auto value = [&](int k) {
    return along_rows ? bev.at<float>(k, index) : bev.at<float>(index, k);
  };
  auto valid = [&](int k) {
    return (along_rows ? mask.at<std::uint8_t>(k, index) : mask.at<std::uint8_t>(index, k)) != 0;
  };
  int best = -1;
  for (int k = 0; k < n; ++k) {
    if (valid(k) && (best < 0 || value(k) > value(best))) best = k;
  }
  if (best < 6 || best >= n - 6 || value(best) < background + 100) return false;
  double sum_w = 0.0, sum_wk = 0.0;
  for (int k = best - 6; k <= best + 6; ++k) {
    if (!valid(k)) return false;
    const double w = value(k) - background;
    sum_w += w;
    sum_wk += w * k;
  }
  *centre = sum_wk / sum_w;
  return true;
}

TEST(BevRemapTest, RenderedFloorLineComesOutStraightAtItsMetricPosition) {
  const CameraModel camera = ReferenceCamera(0.5);
  CameraMount mount;
  mount.roll_rad = 0.8 * kDeg;
  mount.yaw_rad = -1.5 * kDeg;
  const FloorProjection projection(camera, mount);
  constexpr double kBackground = 30.0, kPeak = 180.0, kSigmaM = 0.015;
  const std::vector<HesseLine> truths = {{0.25, 80.0 * kDeg}, {1.6, 4.0 * kDeg}};
  for (const HesseLine& truth : truths) {
    cv::Mat image(camera.height_px(), camera.width_px(), CV_32F, cv::Scalar(kBackground));
    for (int v = 0; v < image.rows; ++v) {
      for (int u = 0; u < image.cols; ++u) {
        const core::Result<Eigen::Vector2d> floor = projection.FloorPointOfPixel({u, v});
        if (!floor.ok()) continue;
        const double d = SignedDistance(truth, *floor);
        image.at<float>(v, u) += kPeak * std::exp(-0.5 * d * d / (kSigmaM * kSigmaM));
      }
    }
    const BevRemap remap(camera, mount, BevRemap::Options{});
    cv::Mat bev;
    remap.Apply(image, &bev);
    const bool along_rows =
        std::abs(std::cos(truth.alpha_rad)) > std::abs(std::sin(truth.alpha_rad));
    const int count = along_rows ? bev.cols : bev.rows;
    std::vector<Eigen::Vector2d> points;
    for (int index = 0; index < count; ++index) {
      double centre = 0.0;
      if (!RidgeCentre(bev, remap.valid_mask(), index, along_rows, kBackground, &centre)) continue;
      const Eigen::Vector2d cell =
          along_rows ? Eigen::Vector2d(index, centre) : Eigen::Vector2d(centre, index);
      points.push_back(remap.grid().FloorPointOfCell(cell));
    }
    ASSERT_GE(points.size(), 60u);
    const std::vector<double> weights(points.size(), 1.0);
    const core::Result<LineFit> fit = FitLineTls(points, weights, 0.001);
    ASSERT_TRUE(fit.ok()) << fit.message();
    EXPECT_NEAR(fit->line.rho_m, truth.rho_m, 0.003);
    EXPECT_NEAR(fit->line.alpha_rad, truth.alpha_rad, 0.1 * kDeg);
    EXPECT_LT(fit->rms_residual_m, 0.002);  // straight in the BEV
  }
}

TEST(BevRemapTest, PinholeWarpPerspectiveAgreesWithRemap) {
  const CameraModel camera = CameraModel::Pinhole(1132.0, 1132.0, 639.5, 511.5, 1280, 1024);
  CameraMount mount;
  mount.roll_rad = -1.0 * kDeg;
  BevRemap::Options options;
  options.fixed_point = false;
  const BevRemap remap(camera, mount, options);
  const Eigen::Matrix3d M = PinholeImageFromCell(remap.grid(), mount, camera.K());
  for (int row = 0; row < remap.grid().rows(); row += 3) {
    for (int col = 0; col < remap.grid().cols(); col += 3) {
      if (remap.valid_mask().at<std::uint8_t>(row, col) == 0) continue;
      const Eigen::Vector3d h = M * Eigen::Vector3d(col, row, 1.0);
      const cv::Vec2f table = remap.pixel_map().at<cv::Vec2f>(row, col);
      ASSERT_NEAR(table[0], h.x() / h.z(), 1e-3);
      ASSERT_NEAR(table[1], h.y() / h.z(), 1e-3);
    }
  }
  cv::Mat noise(1024, 1280, CV_32F), image;
  cv::RNG rng(7);
  rng.fill(noise, cv::RNG::UNIFORM, 0.0, 255.0);
  cv::GaussianBlur(noise, image, cv::Size(0, 0), 4.0);
  cv::normalize(image, image, 0.0, 255.0, cv::NORM_MINMAX);
  image.convertTo(image, CV_8U);
  cv::Mat by_remap, by_warp, diff;
  remap.Apply(image, &by_remap);
  WarpToBevPinhole(image, remap.grid(), mount, camera.K(), &by_warp);
  cv::absdiff(by_remap, by_warp, diff);
  double max_diff = 0.0;
  cv::minMaxLoc(diff, nullptr, &max_diff, nullptr, nullptr, remap.valid_mask());
  EXPECT_LE(max_diff, 2.0);
  EXPECT_LT(cv::mean(diff, remap.valid_mask())[0], 0.3);
  EXPECT_GT(remap.valid_cells(), 10000);
}

// Cells the camera does not see: without fill_unseen they are 0, on both the
// float and the fixed-point path; with it (the default) each holds the grey
// of a seen cell nearest to it (DIST_MASK_5 is within a cell of exact).
// A sharp step edge along the grid (y = y0, bright beyond), rendered with each
// camera pixel the exact share of its footprint across the edge, moved through
// ten sub-cell phases. Its position on the BEV (from the bright share of the
// cells across it, averaged over the rows 1.5-2 m ahead) follows y0 up to an
// error that depends on the phase: with 2 samples per 1 cm cell across, the samples 5 mm apart
// resolve the camera's 2-3 mm pixels only in steps; 4 across halve that.
std::vector<double> EdgeErrorsOverPhases(int samples_across) {
  const CameraModel camera = ReferenceCamera();
  const CameraMount mount;
  const FloorProjection projection(camera, mount);
  // The floor y of each pixel and its footprint across (|dy/du| + |dy/dv|).
  cv::Mat floor_y(camera.height_px(), camera.width_px(), CV_64F, cv::Scalar(-10.0));
  cv::Mat footprint(camera.height_px(), camera.width_px(), CV_64F, cv::Scalar(1.0));
  for (int v = 0; v < floor_y.rows; ++v) {
    for (int u = 0; u < floor_y.cols; ++u) {
      Eigen::Matrix2d J;
      const core::Result<Eigen::Vector2d> p = projection.FloorPointOfPixel({u, v}, &J);
      if (!p.ok() || p->x() < 1.3 || p->x() > 2.2) continue;
      floor_y.at<double>(v, u) = p->y();
      footprint.at<double>(v, u) = std::abs(J(1, 0)) + std::abs(J(1, 1));
    }
  }
  BevRemap::Options options;
  options.supersampling = 2;
  options.supersampling_across = samples_across;
  const BevRemap remap(camera, mount, options);
  constexpr double kDark = 40.0, kBright = 200.0;
  std::vector<double> errors;
  for (int k = 0; k < 10; ++k) {
    const double y0 = 0.3 + 0.001 * k;
    cv::Mat image(camera.height_px(), camera.width_px(), CV_32F);
    for (int v = 0; v < image.rows; ++v) {
      for (int u = 0; u < image.cols; ++u) {
        const double share = std::clamp(
            (floor_y.at<double>(v, u) - y0) / footprint.at<double>(v, u) + 0.5, 0.0, 1.0);
        image.at<float>(v, u) = static_cast<float>(kDark + (kBright - kDark) * share);
      }
    }
    cv::Mat bev;
    remap.Apply(image, &bev);
    double sum_y = 0.0;
    int rows = 0;
    for (int row = 0; row < bev.rows; ++row) {
      const double x = remap.grid().FloorPointOfCell({0.0, static_cast<double>(row)}).x();
      if (x < 1.5 || x > 2.0) continue;
      const float* b = bev.ptr<float>(row);
      // The first column darker than mid-grey; the edge is where the bright
      // share of the cells around it, summed from the bright side, runs out
      // (exact for cells that average the image over their area).
      const double mid = 0.5 * (kDark + kBright);
      int col = 0;
      while (col < bev.cols && b[col] > mid) ++col;
      if (col < 6 || col > bev.cols - 7) continue;
      double bright_cells = 0.0;
      for (int c = col - 6; c <= col + 6; ++c) bright_cells += (b[c] - kDark) / (kBright - kDark);
      const double edge_col = col - 6 - 0.5 + bright_cells;
      sum_y += remap.grid().FloorPointOfCell({edge_col, static_cast<double>(row)}).y();
      ++rows;
    }
    EXPECT_GT(rows, 30);
    errors.push_back(sum_y / std::max(rows, 1) - y0);
  }
  return errors;
}

TEST(BevRemapTest, MoreSamplesAcrossTrackASharpEdgeAlongTheGrid) {
  auto spread = [](const std::vector<double>& e) {
    const auto [lo, hi] = std::minmax_element(e.begin(), e.end());
    return *hi - *lo;
  };
  const std::vector<double> two = EdgeErrorsOverPhases(2);
  const std::vector<double> four = EdgeErrorsOverPhases(4);
  RecordProperty("edge_error_spread_2_across_um", static_cast<int>(1e6 * spread(two)));
  RecordProperty("edge_error_spread_4_across_um", static_cast<int>(1e6 * spread(four)));
  // Measured: 1.79 mm with 2 across, 0.20 mm with 4.
  EXPECT_GT(spread(two), 0.001);
  EXPECT_LT(spread(four), 0.3 * spread(two));
  EXPECT_LT(spread(four), 0.0005);
  for (double e : four) EXPECT_LT(std::abs(e), 0.001);
}

TEST(BevRemapTest, UnseenCellsAreBlackOrTheNearestSeenCell) {
  const CameraModel camera = ReferenceCamera();
  const CameraMount mount;
  cv::Mat noise(1024, 1280, CV_32F), image;
  cv::RNG rng(11);
  rng.fill(noise, cv::RNG::UNIFORM, 0.0, 255.0);
  cv::GaussianBlur(noise, image, cv::Size(0, 0), 3.0);
  cv::normalize(image, image, 1.0, 255.0, cv::NORM_MINMAX);  // no 0 among seen cells
  image.convertTo(image, CV_8U);
  BevRemap::Options black;
  black.fill_unseen = false;
  for (const bool fixed_point : {false, true}) {
    black.fixed_point = fixed_point;
    const BevRemap remap(camera, mount, black);
    cv::Mat bev;
    remap.Apply(image, &bev);
    const cv::Mat unseen = remap.valid_mask() == 0;
    EXPECT_GT(cv::countNonZero(unseen), 1000);
    EXPECT_EQ(cv::countNonZero(bev & unseen), 0) << "fixed_point " << fixed_point;
    EXPECT_EQ(cv::countNonZero(bev), remap.valid_cells());
  }
  const BevRemap remap(camera, mount, BevRemap::Options{});
  cv::Mat bev;
  remap.Apply(image, &bev);
  std::vector<cv::Point> seen;
  cv::findNonZero(remap.valid_mask(), seen);
  ASSERT_FALSE(seen.empty());
  int checked = 0;
  for (int row = 0; row < bev.rows; row += 5) {
    for (int col = 0; col < bev.cols; col += 5) {
      if (remap.valid_mask().at<std::uint8_t>(row, col) != 0) continue;
      double nearest = 1e9;
      for (const cv::Point& p : seen) nearest = std::min(nearest, std::hypot(p.x - col, p.y - row));
      bool matches = false;
      for (const cv::Point& p : seen) {
        matches = matches || (std::hypot(p.x - col, p.y - row) <= nearest + 1.0 &&
                              bev.at<std::uint8_t>(p) == bev.at<std::uint8_t>(row, col));
      }
      EXPECT_TRUE(matches) << "unseen cell (" << col << ", " << row << ") holds "
                           << int(bev.at<std::uint8_t>(row, col));
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(BevRemapTest, RebuildAfterPitchAndHeightChangeMovesPointsAsPredicted) {
  const CameraModel camera = ReferenceCamera();
  CameraMount mount;
  BevRemap remap(camera, mount, BevRemap::Options{});
  const Eigen::Vector2d cell(137.0, 90.0);
  const Eigen::Vector2d floor = remap.grid().FloorPointOfCell(cell);
  const cv::Vec2f before = remap.pixel_map().at<cv::Vec2f>(90, 137);
  mount.pitch_rad += 1.0 * kDeg;  // the camera looks further down
  remap.Rebuild(mount);
  const cv::Vec2f after = remap.pixel_map().at<cv::Vec2f>(90, 137);
  const core::Result<Eigen::Vector2d> predicted =
      FloorProjection(camera, mount).PixelOfFloorPoint(floor);
  ASSERT_TRUE(predicted.ok());
  EXPECT_NEAR(after[0], predicted->x(), 0.01);
  EXPECT_NEAR(after[1], predicted->y(), 0.01);
  // A 1 deg tilt moves the point up the image by about fx * 1 deg = 20 px.
  EXPECT_NEAR(after[1] - before[1], -1132.0 * kDeg, 3.0);
  mount.height_m += 0.03;
  remap.Rebuild(mount);
  const cv::Vec2f raised = remap.pixel_map().at<cv::Vec2f>(90, 137);
  const core::Result<Eigen::Vector2d> predicted_raised =
      FloorProjection(camera, mount).PixelOfFloorPoint(floor);
  ASSERT_TRUE(predicted_raised.ok());
  EXPECT_NEAR(raised[0], predicted_raised->x(), 0.01);
  EXPECT_NEAR(raised[1], predicted_raised->y(), 0.01);
  EXPECT_GT(raised[1], after[1] + 5.0);  // a higher camera sees the point lower
}

// The footprint grid holds the floor a camera sees within its probe square
// (+-6 m around its foot point; compared with a 1 cm probe of the same square)
// but for slivers under 2 cm at the corners (its own probe samples every 2 cm),
// and little else: seen cells reach within 15 cm of each of its edges (its
// margin: one probe cell and 10 cells). Cameras
// looking ahead, behind (yaw 180 deg, mounted behind the axle) and to the side.
TEST(FloorFootprintGridTest, HoldsWhatTheCameraSeesAndLittleElse) {
  const CameraModel camera = ReferenceCamera(0.25);
  std::vector<CameraMount> mounts(3);
  mounts[1].yaw_rad = 180.0 * kDeg;
  mounts[1].forward_m = -0.5;
  mounts[2].yaw_rad = 90.0 * kDeg;
  mounts[2].lateral_m = 0.3;
  mounts[2].pitch_rad = 30.0 * kDeg;
  for (const CameraMount& mount : mounts) {
    // Everything it sees, however coarsely (the resolution test is below).
    const std::optional<BevGridOptions> footprint =
        FloorFootprintGrid(camera, mount, 0.01, 6.0, 1e9);
    ASSERT_TRUE(footprint.has_value());
    BevRemap::Options fine;
    fine.fill_unseen = false;
    fine.grid = {mount.forward_m - 6.0, mount.forward_m + 6.0, mount.lateral_m - 6.0,
                 mount.lateral_m + 6.0, 0.01};
    const BevRemap all(camera, mount, fine);
    double x_min = 1e9, x_max = -1e9, y_min = 1e9, y_max = -1e9;
    for (int row = 0; row < all.grid().rows(); ++row) {
      for (int col = 0; col < all.grid().cols(); ++col) {
        if (all.valid_mask().at<std::uint8_t>(row, col) == 0) continue;
        const Eigen::Vector2d p = all.grid().FloorPointOfCell({col, row});
        x_min = std::min(x_min, p.x());
        x_max = std::max(x_max, p.x());
        y_min = std::min(y_min, p.y());
        y_max = std::max(y_max, p.y());
      }
    }
    ASSERT_LT(x_min, x_max) << "yaw " << mount.yaw_rad;
    const std::string which = "yaw " + std::to_string(mount.yaw_rad / kDeg);
    EXPECT_LE(footprint->x_min_m, x_min + 0.02) << which;
    EXPECT_GE(footprint->x_max_m, x_max - 0.02) << which;
    EXPECT_LE(footprint->y_min_m, y_min + 0.02) << which;
    EXPECT_GE(footprint->y_max_m, y_max - 0.02) << which;
    EXPECT_GT(footprint->x_min_m, x_min - 0.15) << which;
    EXPECT_LT(footprint->x_max_m, x_max + 0.15) << which;
    EXPECT_GT(footprint->y_min_m, y_min - 0.15) << which;
    EXPECT_LT(footprint->y_max_m, y_max + 0.15) << which;
  }
  // The reference camera at full resolution: sees about 0.7-2.3 m ahead, all of it
  // resolved (9 mm per pixel along the floor at the far edge), so the same
  // grid as without the resolution test.
  const std::optional<BevGridOptions> reference =
      FloorFootprintGrid(ReferenceCamera(), CameraMount{}, 0.01);
  const std::optional<BevGridOptions> reference_all =
      FloorFootprintGrid(ReferenceCamera(), CameraMount{}, 0.01, 6.0, 1e9);
  ASSERT_TRUE(reference.has_value() && reference_all.has_value());
  EXPECT_NEAR(reference->x_min_m, 0.7 - 0.12, 0.1);
  EXPECT_NEAR(reference->x_max_m, 2.3 + 0.12, 0.1);
  EXPECT_NEAR(reference->x_max_m, reference_all->x_max_m, 1e-9);
  // The default 30 m square, probed coarsely first, finds the same grid as a
  // 2 cm probe of 6 m.
  const std::optional<BevGridOptions> reference_6m =
      FloorFootprintGrid(ReferenceCamera(), CameraMount{}, 0.01, 6.0);
  ASSERT_TRUE(reference_6m.has_value());
  EXPECT_NEAR(reference->x_min_m, reference_6m->x_min_m, 1e-9);
  EXPECT_NEAR(reference->x_max_m, reference_6m->x_max_m, 1e-9);
  EXPECT_NEAR(reference->y_min_m, reference_6m->y_min_m, 1e-9);
  EXPECT_NEAR(reference->y_max_m, reference_6m->y_max_m, 1e-9);
  // A car's camera, 1.6 m high and level (KITTI's): the road from about 6 m
  // ahead, resolved at 3 cm cells (9 cm per pixel) to about 10 m.
  CameraMount car;
  car.height_m = 1.6;
  car.pitch_rad = 0.0;
  const core::Result<CameraModel> kitti =
      CameraModel::Create("LENSMODEL_PINHOLE", {721.5, 721.5, 609.6, 172.9}, 1242, 375);
  ASSERT_TRUE(kitti.ok());
  const std::optional<BevGridOptions> road = FloorFootprintGrid(*kitti, car, 0.03);
  ASSERT_TRUE(road.has_value());
  EXPECT_NEAR(road->x_min_m, 0.42 + 5.7 - 0.32, 0.3);
  EXPECT_NEAR(road->x_max_m, 0.42 + 10.3 + 0.32, 0.6);
  // At 1 cm cells (3 cm per pixel): hardly any of it.
  const std::optional<BevGridOptions> road_1cm = FloorFootprintGrid(*kitti, car, 0.01);
  EXPECT_TRUE(!road_1cm.has_value() || road_1cm->x_max_m < road->x_max_m - 3.0);
  EXPECT_NEAR(reference->y_max_m, reference_all->y_max_m, 1e-9);
  EXPECT_NEAR(reference->y_min_m, reference_all->y_min_m, 1e-9);
  // A low camera looking towards the horizon sees floor to the probe's edge,
  // but resolves it (a pixel <= 3 cells) only over the first metre or so.
  CameraMount low;
  low.height_m = 0.1;
  low.pitch_rad = 15.0 * kDeg;
  low.forward_m = 0.05;
  const std::optional<BevGridOptions> seen = FloorFootprintGrid(camera, low, 0.01, 6.0, 1e9);
  const std::optional<BevGridOptions> resolved = FloorFootprintGrid(camera, low, 0.01);
  ASSERT_TRUE(seen.has_value() && resolved.has_value());
  EXPECT_GT(seen->x_max_m, 6.0);
  EXPECT_LT(resolved->x_max_m, 1.5);
  EXPECT_GT(resolved->x_max_m, 0.4);
  EXPECT_GT(FloorFootprintGrid(camera, low, 0.05)->x_max_m, resolved->x_max_m + 0.5);
  // Looking up: no floor.
  CameraMount up;
  up.pitch_rad = -40.0 * kDeg;
  EXPECT_FALSE(FloorFootprintGrid(camera, up, 0.01).has_value());
}

TEST(ResolveBevGridTest, GivenRangesReplaceTheFootprintsAndErrorsSayWhy) {
  const CameraModel camera = ReferenceCamera(0.25);
  const CameraMount mount;
  const std::optional<BevGridOptions> footprint = FloorFootprintGrid(camera, mount, 0.02);
  ASSERT_TRUE(footprint.has_value());
  BevExtent extent;
  extent.cell_m = 0.02;
  core::Result<BevGridOptions> grid = ResolveBevGrid(camera, mount, extent);
  ASSERT_TRUE(grid.ok()) << grid.message();
  EXPECT_EQ(grid->x_min_m, footprint->x_min_m);
  EXPECT_EQ(grid->y_max_m, footprint->y_max_m);
  EXPECT_EQ(grid->cell_m, 0.02);
  extent.x_m = {{1.0, 2.0}};
  grid = ResolveBevGrid(camera, mount, extent);
  ASSERT_TRUE(grid.ok()) << grid.message();
  EXPECT_EQ(grid->x_min_m, 1.0);
  EXPECT_EQ(grid->x_max_m, 2.0);
  EXPECT_EQ(grid->y_min_m, footprint->y_min_m);
  extent.y_m = {{-0.5, 0.25}};
  grid = ResolveBevGrid(camera, mount, extent);
  ASSERT_TRUE(grid.ok()) << grid.message();
  EXPECT_EQ(grid->y_min_m, -0.5);
  EXPECT_EQ(grid->y_max_m, 0.25);

  BevExtent bad;
  bad.x_m = {{2.0, 1.0}};
  EXPECT_NE(ResolveBevGrid(camera, mount, bad).message().find("x_m"), std::string::npos);
  bad = BevExtent{};
  bad.cell_m = 0.0;
  EXPECT_NE(ResolveBevGrid(camera, mount, bad).message().find("cell_m"), std::string::npos);
  bad = BevExtent{};
  bad.x_m = {{0.0, 50.0}};
  bad.cell_m = 0.001;
  EXPECT_NE(ResolveBevGrid(camera, mount, bad).message().find("4096"), std::string::npos);
  bad = BevExtent{};
  bad.x_m = {{-3.0, -2.0}};  // behind the camera
  bad.y_m = {{-1.0, 1.0}};
  EXPECT_NE(ResolveBevGrid(camera, mount, bad).message().find("sees none"), std::string::npos);
  CameraMount up;
  up.pitch_rad = -40.0 * kDeg;
  EXPECT_NE(ResolveBevGrid(camera, up, BevExtent{}).message().find("sees no floor"),
            std::string::npos);
}

}  // namespace
}  // namespace groundline::perception
