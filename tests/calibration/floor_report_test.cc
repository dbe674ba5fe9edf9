// The floor commissioning report: the rectified floor puts the rendered tags
// on their surveyed outlines, the verdict names what to fix, the thresholds
// config reports its errors by file, line and key, and the survey error widens
// the mount's bounds enough to hold the truth.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <numbers>
#include <random>

#include "commissioning_fixture.h"
#include "groundline/calibration/calibration_report.h"
#include "groundline/calibration/floor_calibration.h"
#include "groundline/calibration/floor_projection.h"
#include "groundline/calibration/floor_rectification.h"
#include "groundline/calibration/tag_detection.h"
#include "groundline/core/random_draws.h"
#include "groundline/sim/commissioning_scene.h"
#include "test_data.h"
#include "test_units.h"

namespace groundline::calibration {
namespace {

using ::groundline::testing::CommissioningSceneOrFail;
using ::groundline::testing::kDeg;

// Every tag corner of the rectified floor, detected by libapriltag in the
// raster, against its surveyed position: the largest distance in metres and
// the number of tags found.
std::pair<double, int> WorstCornerOffset(const FloorRaster& raster, const TagLayout& layout) {
  double worst = 0.0;
  int found = 0;
  for (const TagDetection& d :
       DetectTags(raster.grey.data(), raster.width_px, raster.height_px, raster.width_px)) {
    const SurveyedTag* tag = layout.FindTag(d.id);
    if (tag == nullptr) continue;
    ++found;
    const auto surveyed = tag->CornersInFrame();
    for (int k = 0; k < 4; ++k) {
      // Detector pixels have their centres at integers, raster cells at +0.5.
      const Eigen::Vector2d floor =
          raster.FloorOfRaster(d.corners_px[k] + Eigen::Vector2d(0.5, 0.5));
      worst = std::max(worst, (floor - surveyed[k]).norm());
    }
  }
  return {worst, found};
}

TEST(FloorRectification, RenderedTagsLandOnTheirSurveyedOutlines) {
  sim::CommissioningOptions options = sim::CommissioningOptions::Small();
  options.poses = 2;
  const sim::CommissioningScene scene = CommissioningSceneOrFail(options);
  const std::vector<sim::GreyImage> images = sim::RenderCommissioningImages(scene, options).value();
  std::vector<FloorImageView> views;
  for (std::size_t i = 0; i < images.size(); ++i) {
    views.push_back({images[i].pixels.data(), images[i].width_px, images[i].height_px,
                     images[i].width_px, scene.layout.vehicle_poses[i].T_floor_base});
  }
  Eigen::Vector2d lo(1e9, 1e9), hi(-1e9, -1e9);
  for (const SurveyedTag& t : scene.layout.tags) {
    for (const Eigen::Vector2d& p : t.CornersInFrame()) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  FloorRectificationOptions rectification;
  rectification.resolution_m = 0.002;
  const FloorRaster raster =
      RectifyFloor(scene.camera, scene.true_mount, views, lo, hi, rectification).value();
  EXPECT_NEAR(raster.width_px * raster.resolution_m, hi.y() - lo.y(), raster.resolution_m);
  const Eigen::Vector2d p(0.9, -0.2);
  EXPECT_LT((raster.FloorOfRaster(raster.RasterOfFloor(p)) - p).norm(), 1e-12);

  const auto [worst_m, found] = WorstCornerOffset(raster, scene.layout);
  EXPECT_GE(found, 4);
  EXPECT_LT(worst_m, 0.003) << "a rectified tag corner is off its surveyed outline";

  // A mount off by half a degree of pitch moves the tags off their outlines.
  CameraMount wrong = scene.true_mount;
  wrong.pitch_rad += 0.5 * kDeg;
  const FloorRaster off = RectifyFloor(scene.camera, wrong, views, lo, hi, rectification).value();
  EXPECT_GT(WorstCornerOffset(off, scene.layout).first, 0.008);

  // Images of the wrong size are refused.
  views[0].width_px = 100;
  EXPECT_FALSE(RectifyFloor(scene.camera, scene.true_mount, views, lo, hi, rectification).ok());
}

// Corners of the scene's tags projected from the true mount with 0.3 px
// noise; the surveyed corner positions carry survey noise of survey_sigma_m
// (the same in every image), true positions are used for the pixels.
std::vector<FloorImage> Corners(const sim::CommissioningScene& scene, double survey_sigma_m,
                                std::mt19937_64& rng) {
  std::normal_distribution<double> pixel_noise(0.0, 0.3), survey_noise(0.0, survey_sigma_m);
  std::map<std::pair<int, int>, Eigen::Vector2d> survey_error;
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
        auto [it, added] = survey_error.try_emplace({tag.id, c}, Eigen::Vector2d::Zero());
        if (added && survey_sigma_m > 0.0) it->second = {survey_noise(rng), survey_noise(rng)};
        seen.push_back(
            {tag.id, c, corners[c] + it->second, *px + core::DrawVector<2>(pixel_noise, rng)});
      }
      if (seen.size() == 4) im.corners.insert(im.corners.end(), seen.begin(), seen.end());
    }
    images.push_back(std::move(im));
  }
  return images;
}

FloorCalibration Solved(const sim::CommissioningScene& scene, std::vector<FloorImage> images) {
  FloorCalibration c;
  c.solution = SolveFloorExtrinsics(scene.camera, images, {}).value();
  c.images = std::move(images);
  for (int i = 0; i < 3; ++i) {
    c.bev[i] =
        BevErrorAhead(c.solution.mount, c.solution.covariance, i == 2 ? 4.0 : i + 1.0).value();
  }
  return c;
}

bool Contains(const std::vector<std::string>& lines, const std::string& text) {
  for (const std::string& l : lines) {
    if (l.find(text) != std::string::npos) return true;
  }
  return false;
}

TEST(FloorVerdict, PassesAndNamesTheTagAndImageRegionToFix) {
  const sim::CommissioningScene scene =
      CommissioningSceneOrFail(sim::CommissioningOptions::Small());
  std::mt19937_64 rng(11);
  const std::vector<FloorImage> clean = Corners(scene, 0.0, rng);
  FloorCalibration good = Solved(scene, clean);
  JudgeFloorCalibration(scene.camera, {}, &good);
  EXPECT_TRUE(good.pass) << good.verdict;
  EXPECT_EQ(good.verdict, "PASS");
  ASSERT_FALSE(good.tags.empty());
  EXPECT_LT(good.tags.front().rms_px, 1.0);
  for (int n : good.quadrant_corners) EXPECT_GE(n, 4);

  // One tag surveyed 2 cm off: that tag fails and is named for re-survey.
  std::vector<FloorImage> moved = clean;
  const int bad_tag = moved[0].corners.front().tag_id;
  for (FloorImage& im : moved) {
    for (FloorCorner& c : im.corners) {
      if (c.tag_id == bad_tag) c.floor_m += Eigen::Vector2d(0.02, 0.0);
    }
  }
  FloorCalibration off = Solved(scene, moved);
  JudgeFloorCalibration(scene.camera, {}, &off);
  EXPECT_FALSE(off.pass);
  EXPECT_EQ(off.tags.front().id, bad_tag);
  EXPECT_TRUE(Contains(off.advice, "re-survey tag " + std::to_string(bad_tag))) << off.verdict;

  // No corner in the bottom-left quadrant of any image: that region is named.
  std::vector<FloorImage> cut = clean;
  const double cx = 0.5 * (scene.camera.width_px() - 1), cy = 0.5 * (scene.camera.height_px() - 1);
  for (FloorImage& im : cut) {
    std::erase_if(im.corners,
                  [&](const FloorCorner& c) { return c.pixel.x() < cx && c.pixel.y() >= cy; });
  }
  FloorCalibration uncovered = Solved(scene, cut);
  JudgeFloorCalibration(scene.camera, {}, &uncovered);
  EXPECT_FALSE(uncovered.pass);
  EXPECT_EQ(uncovered.quadrant_corners[2], 0);
  EXPECT_TRUE(Contains(uncovered.failures, "bottom-left image quadrant")) << uncovered.verdict;
  EXPECT_TRUE(Contains(uncovered.advice, "appear in the bottom-left of the image"));

  // A BEV limit the solution cannot meet names the mount parameter to pin down.
  FloorReportThresholds strict;
  strict.max_bev_error_2m_mm = 1e-3;
  JudgeFloorCalibration(scene.camera, strict, &good);
  EXPECT_FALSE(good.pass);
  EXPECT_TRUE(Contains(good.failures, "BEV error at 2 m")) << good.verdict;
  EXPECT_TRUE(Contains(good.advice, "the mount is too uncertain, most of all its "));
}

TEST(FloorVerdict, AnImageAtAWrongVehiclePoseIsLeftOutAndNamed) {
  sim::CommissioningOptions options = sim::CommissioningOptions::Small();
  options.poses = 4;
  const sim::CommissioningScene scene = CommissioningSceneOrFail(options);
  std::mt19937_64 rng(21);
  std::vector<FloorImage> images = Corners(scene, 0.0, rng);
  ASSERT_EQ(images.size(), 4u);
  // Image 2 was taken elsewhere: its surveyed pose is 0.4 m and 10 deg off.
  images[2].T_floor_base = images[2].T_floor_base * core::SE2(0.4, 0.1, 10.0 * kDeg);
  FloorCalibration c = Solved(scene, images);
  EXPECT_GT(c.solution.gated_corners, 0);
  EXPECT_NEAR(c.solution.mount.height_m, scene.true_mount.height_m, 1e-3);
  EXPECT_NEAR(c.solution.mount.pitch_rad, scene.true_mount.pitch_rad, 0.05 * kDeg);
  JudgeFloorCalibration(scene.camera, {}, &c);
  EXPECT_FALSE(c.pass);
  EXPECT_EQ(c.image_failed, std::vector<bool>({false, false, true, false}));
  EXPECT_TRUE(Contains(c.advice, "drop or retake image " + images[2].name)) << c.verdict;
  for (const TagResidual& t : c.tags) EXPECT_LT(t.rms_px, 1.0) << "tag " << t.id;
}

TEST(FloorVerdict, ThresholdsConfigErrorsNameTheFileLineAndKey) {
  const std::filesystem::path dir = groundline::testing::ScratchDir("floor_thresholds");
  std::ofstream(dir / "ok.yaml") << "intrinsics_report:\n  max_rms_px: 0.4\nfloor_report:\n"
                                    "  max_bev_error_2m_mm: 3.5\n  require_all_quadrants: false\n";
  core::Result<FloorReportThresholds> t = ReadFloorReportThresholds(dir / "ok.yaml");
  ASSERT_TRUE(t.ok()) << t.message();
  EXPECT_DOUBLE_EQ(t->max_bev_error_2m_mm, 3.5);
  EXPECT_DOUBLE_EQ(t->max_image_rms_px, 0.5);
  EXPECT_FALSE(t->require_all_quadrants);

  std::ofstream(dir / "unknown.yaml") << "floor_report:\n  max_bev_error_2m_mm: 3\n"
                                         "  max_bev_mm: 4\n";
  t = ReadFloorReportThresholds(dir / "unknown.yaml");
  ASSERT_FALSE(t.ok());
  EXPECT_NE(t.message().find("unknown.yaml:3: key 'floor_report.max_bev_mm': unknown key"),
            std::string::npos)
      << t.message();

  std::ofstream(dir / "type.yaml") << "floor_report:\n  max_tag_rms_px: one\n";
  t = ReadFloorReportThresholds(dir / "type.yaml");
  ASSERT_FALSE(t.ok());
  EXPECT_NE(t.message().find("type.yaml:2: key 'floor_report.max_tag_rms_px': expected a number, "
                             "got 'one'"),
            std::string::npos)
      << t.message();

  std::ofstream(dir / "range.yaml") << "floor_report:\n  min_corners_per_quadrant: 0\n";
  t = ReadFloorReportThresholds(dir / "range.yaml");
  ASSERT_FALSE(t.ok());
  EXPECT_NE(t.message().find("min_corners_per_quadrant must be >= 1"), std::string::npos);

  // The intrinsics thresholds share the reader: same messages.
  std::ofstream(dir / "intr.yaml") << "intrinsics_report:\n  max_rms_px: 0.4\n  worst: 2\n";
  const core::Result<ReportThresholds> r = ReadReportThresholds(dir / "intr.yaml");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("intr.yaml:3: key 'intrinsics_report.worst'"), std::string::npos)
      << r.message();
}

TEST(FloorExtrinsicsCovariance, SurveyErrorWidensTheBoundsToHoldTheTruth) {
  const sim::CommissioningScene scene =
      CommissioningSceneOrFail(sim::CommissioningOptions::Small());
  constexpr int kTrials = 30;
  constexpr double kSurveyM = 0.005;
  int inside_with = 0, inside_without = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    std::mt19937_64 rng(300 + trial);
    const std::vector<FloorImage> images = Corners(scene, kSurveyM, rng);
    FloorExtrinsicsOptions with;
    with.survey_sigma_m = kSurveyM;
    const FloorExtrinsicsResult a = SolveFloorExtrinsics(scene.camera, images, with).value();
    const FloorExtrinsicsResult b = SolveFloorExtrinsics(scene.camera, images, {}).value();
    EXPECT_DOUBLE_EQ(a.survey_sigma_m, kSurveyM);
    // Height: the parameter the survey error moves most in this scene.
    const double err = std::abs(a.mount.height_m - scene.true_mount.height_m);
    if (err <= 3.0 * std::sqrt(a.covariance(0, 0))) ++inside_with;
    if (std::abs(b.mount.height_m - scene.true_mount.height_m) <=
        3.0 * std::sqrt(b.covariance(0, 0)))
      ++inside_without;
    EXPECT_GT(a.covariance(0, 0), b.covariance(0, 0));
  }
  std::printf("height inside 3 sigma: %d / %d with the survey term, %d without\n", inside_with,
              kTrials, inside_without);
  EXPECT_GE(inside_with, kTrials - 2);

  // Noise-free corners: the a posteriori sigma is ~0, the covariance keeps the floor.
  std::mt19937_64 rng(1);
  std::vector<FloorImage> exact = Corners(scene, 0.0, rng);
  for (FloorImage& im : exact) {
    for (FloorCorner& c : im.corners) {
      c.pixel =
          PredictFloorPixel(scene.camera, scene.true_mount, im.T_floor_base, c.floor_m).value();
    }
  }
  const FloorExtrinsicsResult r = SolveFloorExtrinsics(scene.camera, exact, {}).value();
  EXPECT_LT(r.a_posteriori_sigma_px, 1e-6);
  EXPECT_DOUBLE_EQ(r.sigma_px, 0.3);
}

// The intrinsics' projection uncertainty reaches the floor through the
// solved mount: a constant Var(q) = sigma^2 I gives sigma times the floor
// displacement of a one-pixel step in u and in v (central differences of
// FloorPointOfPixel), and it adds to the mount's part.
TEST(BevErrorBudget, IntrinsicsUncertaintyIsCarriedToTheFloorThroughTheMount) {
  const sim::CommissioningScene scene =
      CommissioningSceneOrFail(sim::CommissioningOptions::Small());
  std::mt19937_64 rng(3);
  FloorCalibration c = Solved(scene, Corners(scene, 0.0, rng));
  const auto constant_map = [](double range_m, double var_px2) {
    IntrinsicsReportSummary::CovarianceMap m;
    m.range_m = range_m;
    m.cells_x = 32;
    m.cells_y = 24;
    m.covariance_px2.assign(32 * 24, var_px2 * Eigen::Matrix2d::Identity());
    return m;
  };
  IntrinsicsReportSummary intrinsics;
  constexpr double kSigmaPx = 0.5;
  intrinsics.covariance_maps = {constant_map(1.0, kSigmaPx * kSigmaPx),
                                constant_map(4.0, kSigmaPx * kSigmaPx)};
  AddIntrinsicsToBev(scene.camera, intrinsics, &c);
  ASSERT_EQ(c.bev_budget.size(), 3u);
  const FloorProjection floor(scene.camera, c.solution.mount);
  // The small scene's camera sees 1 m ahead; 2 and 4 m are above its image.
  ASSERT_TRUE(c.bev_budget[0].known);
  for (const BevErrorBudget& b : c.bev_budget) {
    EXPECT_EQ(b.known, floor.PixelOfFloorPoint({b.distance_m, 0.0}).ok() &&
                           scene.camera.InImage(*floor.PixelOfFloorPoint({b.distance_m, 0.0})));
    if (!b.known) continue;
    const Eigen::Vector2d q = floor.PixelOfFloorPoint({b.distance_m, 0.0}).value();
    EXPECT_NEAR((b.pixel - q).norm(), 0.0, 1e-9);
    double sum_sq = 0.0;
    for (const Eigen::Vector2d& step : {Eigen::Vector2d(0.5, 0), Eigen::Vector2d(0, 0.5)}) {
      sum_sq +=
          (floor.FloorPointOfPixel(q + step).value() - floor.FloorPointOfPixel(q - step).value())
              .squaredNorm();
    }
    const double expected_mm = 1000.0 * kSigmaPx * std::sqrt(sum_sq);
    EXPECT_NEAR(b.intrinsics_rms_mm, expected_mm, 0.01 * expected_mm) << b.distance_m;
    EXPECT_NEAR(
        b.total_rms_mm * b.total_rms_mm,
        b.intrinsics_rms_mm * b.intrinsics_rms_mm + b.extrinsics_rms_mm * b.extrinsics_rms_mm,
        1e-9 * b.total_rms_mm * b.total_rms_mm);
    EXPECT_GT(b.intrinsics_rms_mm, 0.0);
    std::printf(
        "BEV %.0f m ahead: pixel %.0f,%.0f range %.2f m, mount %.3f mm, intrinsics "
        "(0.5 px) %.3f mm, both %.3f mm\n",
        b.distance_m, b.pixel.x(), b.pixel.y(), b.range_m, b.extrinsics_rms_mm, b.intrinsics_rms_mm,
        b.total_rms_mm);
  }
  // Between the maps' ranges the variance is linear in range; a cell without
  // a covariance leaves the point unknown.
  intrinsics.covariance_maps = {constant_map(0.5, 0.0), constant_map(100.0, 1.0)};
  AddIntrinsicsToBev(scene.camera, intrinsics, &c);
  for (const BevErrorBudget& b : c.bev_budget) {
    if (!b.known) continue;
    const Eigen::Vector2d q = b.pixel;
    double sum_sq = 0.0;
    for (const Eigen::Vector2d& step : {Eigen::Vector2d(0.5, 0), Eigen::Vector2d(0, 0.5)}) {
      sum_sq +=
          (floor.FloorPointOfPixel(q + step).value() - floor.FloorPointOfPixel(q - step).value())
              .squaredNorm();
    }
    const double var = (b.range_m - 0.5) / 99.5;
    EXPECT_NEAR(b.intrinsics_rms_mm, 1000.0 * std::sqrt(var * sum_sq),
                0.01 * b.intrinsics_rms_mm + 1e-9);
  }
  for (auto& m : intrinsics.covariance_maps) {
    m.covariance_px2.assign(m.covariance_px2.size(), Eigen::Matrix2d::Constant(std::nan("")));
  }
  AddIntrinsicsToBev(scene.camera, intrinsics, &c);
  for (const BevErrorBudget& b : c.bev_budget) EXPECT_FALSE(b.known);
}

}  // namespace
}  // namespace groundline::calibration
