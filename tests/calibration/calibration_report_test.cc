// The verdict, the advice and the report files of an intrinsic calibration.
#include "groundline/calibration/calibration_report.h"

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "groundline/calibration/floor_calibration.h"
#include "groundline/calibration/mrcal_cameramodel_io.h"
#include "groundline/calibration/opencv_calibration_io.h"
#include "groundline/calibration/ros_camera_info_io.h"
#include "synthetic_views.h"
#include "test_data.h"

namespace groundline::calibration {
namespace {

// 24 views: above the report's default min_views (20).
IntrinsicCalibration Calibrate(bool top_left_only, unsigned seed = 7, int n_views = 24) {
  const CalibTarget target = testing::SyntheticAprilGrid();
  const BoardGrid grid = MakeBoardGrid(target);
  const std::vector<CalibrationView> views = testing::SyntheticViews(
      testing::TrueOpencv8Camera(), target, grid, n_views, 0.1, seed, top_left_only,
      /*reach_borders=*/!top_left_only);
  core::Result<IntrinsicCalibration> cal =
      CalibrateIntrinsics(views, grid, 640, 480, IntrinsicCalibrationOptions{});
  EXPECT_TRUE(cal.ok()) << cal.message();
  return *cal;
}

using ::groundline::testing::ReadText;

TEST(CalibrationReport, AGoodCalibrationPassesWithEveryQuadrantCovered) {
  const IntrinsicCalibration cal = Calibrate(false);
  const CalibrationReport report = BuildCalibrationReport(cal, "grid", {}, ReportThresholds{});
  EXPECT_TRUE(report.pass);
  for (const std::string& f : report.failures) ADD_FAILURE() << f;
  for (int n : report.border_corners) EXPECT_GE(n, 5);
  ASSERT_EQ(report.uncertainty.size(), 4u);
  EXPECT_LE(report.uncertainty.back().worst_px, 0.25);
  int total = 0;
  for (int n : report.quadrant_corners) {
    EXPECT_GE(n, 10);
    total += n;
  }
  EXPECT_EQ(total, cal.summary.points - cal.summary.outliers);
  ASSERT_EQ(report.views_by_rms.size(), cal.views.size());
  EXPECT_GE(cal.views[report.views_by_rms.front()].rms_px,
            cal.views[report.views_by_rms.back()].rms_px);
}

TEST(CalibrationReport, UncoveredQuadrantsFailAndSayWhereToTakeViews) {
  const IntrinsicCalibration cal = Calibrate(true);
  const CalibrationReport report = BuildCalibrationReport(cal, "grid", {}, ReportThresholds{});
  EXPECT_FALSE(report.pass);
  EXPECT_LT(report.quadrant_corners[3], 10);  // bottom-right
  bool advised = false;
  for (const std::string& a : report.advice) {
    advised = advised || a.find("bottom-right of the image") != std::string::npos;
  }
  EXPECT_TRUE(advised);
  // Without the coverage rules, what is left is the projection uncertainty
  // far from the board: the views in one corner leave the rest of the imager
  // unknown, and the report says so.
  ReportThresholds lenient;
  lenient.require_all_quadrants = false;
  lenient.require_border_coverage = false;
  const CalibrationReport uncovered = BuildCalibrationReport(cal, "grid", {}, lenient);
  EXPECT_FALSE(uncovered.pass);
  ASSERT_FALSE(uncovered.uncertainty.empty());
  EXPECT_GT(uncovered.uncertainty.back().worst_px, lenient.max_projection_uncertainty_px);
  lenient.max_projection_uncertainty_px = 1e6;
  lenient.min_tilt_deg = 0.0;
  EXPECT_TRUE(BuildCalibrationReport(cal, "grid", {}, lenient).pass)
      << BuildCalibrationReport(cal, "grid", {}, lenient).failures.front();
}

TEST(CalibrationReport, TooFewViewsFailAndSayHowManyMoreToCapture) {
  const IntrinsicCalibration cal = Calibrate(false, 7, 12);
  const CalibrationReport report = BuildCalibrationReport(cal, "grid", {}, ReportThresholds{});
  EXPECT_FALSE(report.pass);
  ASSERT_FALSE(report.failures.empty());
  EXPECT_EQ(report.failures[0], "12 views < 20");
  EXPECT_NE(report.advice[0].find("capture 8 more view(s)"), std::string::npos) << report.advice[0];
}

TEST(CalibrationReport, WhatTheLiveGuidanceStillMissedIsAFailure) {
  const IntrinsicCalibration cal = Calibrate(false);
  const CalibrationReport report =
      BuildCalibrationReport(cal, "grid", {}, ReportThresholds{},
                             {"hold the board in the image's top-left (1 of 10 corners)"});
  EXPECT_FALSE(report.pass);
  ASSERT_EQ(report.failures.size(), 1u);
  EXPECT_EQ(report.failures[0],
            "live guidance: coverage incomplete: hold the board in the image's top-left (1 of 10 "
            "corners)");
  EXPECT_EQ(report.advice[0], "hold the board in the image's top-left (1 of 10 corners)");
}

TEST(CalibrationReport, ABadImageFailsTheRmsAndIsNamedForDropping) {
  IntrinsicCalibration cal = Calibrate(false);
  // One view far worse than the rest (as if its corners were misdetected).
  ViewResult& bad = cal.views[4];
  bad.rms_px = 3.0;
  bad.worst_px = 4.0;
  cal.summary.rms_px = 0.9;
  cal.summary.worst_px = 4.0;
  const CalibrationReport report = BuildCalibrationReport(cal, "grid", {}, ReportThresholds{});
  EXPECT_FALSE(report.pass);
  EXPECT_EQ(report.failures.size(), 2u);
  EXPECT_EQ(report.views_by_rms.front(), 4);
  ASSERT_FALSE(report.advice.empty());
  EXPECT_NE(report.advice[0].find("drop or retake image " + bad.name), std::string::npos)
      << report.advice[0];
}

TEST(CalibrationReport, FilesAreWrittenAndReadBackByMrcalOpenCvAndRosReaders) {
  const IntrinsicCalibration cal = Calibrate(false);
  const CalibrationReport report =
      BuildCalibrationReport(cal, "grid", {{"blurry.png", "no tag found"}}, ReportThresholds{});
  const std::filesystem::path dir = groundline::testing::ScratchDir("report");
  ASSERT_TRUE(WriteCalibrationOutputs(dir / "out", report, cal).ok());
  core::Result<MrcalCameraModelFile> mrcal = ReadMrcalCameraModel(dir / "out/camera.cameramodel");
  ASSERT_TRUE(mrcal.ok()) << mrcal.message();
  EXPECT_EQ(mrcal->camera.intrinsics(), cal.camera.intrinsics());  // bit for bit
  core::Result<CameraModel> opencv = ReadOpenCvCalibration(dir / "out/camera_opencv.yaml");
  ASSERT_TRUE(opencv.ok()) << opencv.message();
  EXPECT_EQ(opencv->intrinsics(), cal.camera.intrinsics());
  core::Result<RosCameraInfo> ros = ReadRosCameraInfo(dir / "out/camera_info.yaml");
  ASSERT_TRUE(ros.ok()) << ros.message();
  EXPECT_EQ(ros->camera.lens_model(), "LENSMODEL_OPENCV8");

  const nlohmann::json json = nlohmann::json::parse(ReadText(dir / "out/report.json"));
  EXPECT_EQ(json["verdict"], "PASS");
  EXPECT_DOUBLE_EQ(json["rms_px"].get<double>(), cal.summary.rms_px);
  EXPECT_EQ(json["views"].size(), cal.views.size());
  EXPECT_EQ(json["rejected_images"][0]["image"], "blurry.png");
  // The floor report folds this file in (commissioning report).
  const core::Result<IntrinsicsReportSummary> summary =
      ReadIntrinsicsReportSummary(dir / "out/report.json");
  ASSERT_TRUE(summary.ok()) << summary.message();
  EXPECT_TRUE(summary->pass);
  EXPECT_DOUBLE_EQ(summary->rms_px, cal.summary.rms_px);
  EXPECT_EQ(summary->views, static_cast<int>(cal.views.size()));
  EXPECT_EQ(summary->quadrant_corners, report.quadrant_corners);
  std::ofstream(dir / "partial.json") << R"({"format": "groundline-intrinsics-report", )"
                                         R"("verdict": "PASS", "failures": []})";
  const core::Result<IntrinsicsReportSummary> partial =
      ReadIntrinsicsReportSummary(dir / "partial.json");
  ASSERT_FALSE(partial.ok());
  EXPECT_NE(partial.message().find("partial.json: field 'advice'"), std::string::npos)
      << partial.message();
  const std::string html = ReadText(dir / "out/report.html");
  EXPECT_NE(html.find("PASS"), std::string::npos);
  EXPECT_EQ(html.find("<img"), std::string::npos);  // self-contained: inline SVG only
  EXPECT_EQ(std::count(html.begin(), html.end(), '\n'), 1);
  std::size_t svgs = 0;
  for (std::size_t at = html.find("<svg"); at != std::string::npos;
       at = html.find("<svg", at + 1)) {
    ++svgs;
  }
  EXPECT_EQ(svgs, 4u);  // residual field, histogram, coverage, projection uncertainty
  EXPECT_NE(html.find("Projection uncertainty"), std::string::npos);
  // mrcal's optimization_inputs travel with the model; mrcal's parser reads it.
  const std::string model = ReadText(dir / "out/camera.cameramodel");
  EXPECT_NE(model.find("'optimization_inputs': b'"), std::string::npos);
  EXPECT_NE(model.find("'icam_intrinsics': 0,"), std::string::npos);
  EXPECT_EQ(json["camera_fingerprint"], CameraFingerprint(cal.camera));
  EXPECT_EQ(summary->camera_fingerprint, CameraFingerprint(mrcal->camera));
  EXPECT_NE(html.find("blurry.png"), std::string::npos);
  // No temporary file is left behind.
  for (const auto& entry : std::filesystem::directory_iterator(dir / "out")) {
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
  }
}

// A commissioning report folds in only the intrinsics of the camera the floor
// calibration used: another imager size, lens model or model is refused.
TEST(CalibrationReport, TheCombinedReportRefusesAnotherCamerasIntrinsics) {
  const IntrinsicCalibration cal = Calibrate(false);
  const CalibrationReport report = BuildCalibrationReport(cal, "grid", {}, ReportThresholds{});
  const std::filesystem::path dir = groundline::testing::ScratchDir("same_camera");
  ASSERT_TRUE(WriteCalibrationOutputs(dir, report, cal).ok());
  const core::Result<IntrinsicsReportSummary> summary =
      ReadIntrinsicsReportSummary(dir / "report.json");
  ASSERT_TRUE(summary.ok()) << summary.message();
  const core::Result<MrcalCameraModelFile> own = ReadMrcalCameraModel(dir / "camera.cameramodel");
  ASSERT_TRUE(own.ok());
  EXPECT_TRUE(CheckSameCamera(*summary, own->camera, "camera.cameramodel").ok());

  const CameraModel big =
      *CameraModel::Create("LENSMODEL_OPENCV8", cal.camera.intrinsics(), 1280, 1024);
  const core::Status size = CheckSameCamera(*summary, big, "scene/camera.cameramodel");
  ASSERT_FALSE(size.ok());
  EXPECT_NE(size.message().find("is for a 640x480 px imager, the camera model is 1280x1024 px"),
            std::string::npos)
      << size.message();
  EXPECT_NE(size.message().find("scene/camera.cameramodel"), std::string::npos);

  const CameraModel opencv5 = *CameraModel::Create(
      "LENSMODEL_OPENCV5",
      std::vector<double>(cal.camera.intrinsics().begin(), cal.camera.intrinsics().begin() + 9),
      640, 480);
  const core::Status lens = CheckSameCamera(*summary, opencv5, "b.cameramodel");
  ASSERT_FALSE(lens.ok());
  EXPECT_NE(lens.message().find("lens model LENSMODEL_OPENCV8 in the report"), std::string::npos)
      << lens.message();

  std::vector<double> q = cal.camera.intrinsics();
  q[2] += 5.0;  // cx moved by 5 px: another calibration of the same imager
  const CameraModel moved = *CameraModel::Create("LENSMODEL_OPENCV8", q, 640, 480);
  const core::Status hash = CheckSameCamera(*summary, moved, "c.cameramodel");
  ASSERT_FALSE(hash.ok());
  EXPECT_NE(hash.message().find("model fingerprint"), std::string::npos) << hash.message();
}

TEST(CalibrationReport, ThresholdsAreReadFromAConfigAndCheckedWithNamedErrors) {
  const std::filesystem::path dir = groundline::testing::ScratchDir("thresholds");
  std::ofstream(dir / "ok.yaml") << "intrinsics_report:\n  max_rms_px: 0.3\n"
                                    "  require_all_quadrants: false\n";
  core::Result<ReportThresholds> t = ReadReportThresholds(dir / "ok.yaml");
  ASSERT_TRUE(t.ok()) << t.message();
  EXPECT_DOUBLE_EQ(t->max_rms_px, 0.3);
  EXPECT_DOUBLE_EQ(t->max_worst_px, 2.0);
  EXPECT_FALSE(t->require_all_quadrants);
  std::ofstream(dir / "rules.yaml") << "intrinsics_report:\n  min_views: 30\n"
                                       "  min_corners_per_border_zone: 8\n"
                                       "  max_projection_uncertainty_px: 0.1\n"
                                       "  uncertainty_range_m: 1.5\n  floor_top_fraction: 0.3\n";
  t = ReadReportThresholds(dir / "rules.yaml");
  ASSERT_TRUE(t.ok()) << t.message();
  EXPECT_EQ(t->min_views, 30);
  EXPECT_EQ(t->min_corners_per_border_zone, 8);
  EXPECT_DOUBLE_EQ(t->max_projection_uncertainty_px, 0.1);
  EXPECT_DOUBLE_EQ(t->uncertainty_range_m, 1.5);
  EXPECT_DOUBLE_EQ(t->floor_top_fraction, 0.3);
  std::ofstream(dir / "bad_fraction.yaml") << "intrinsics_report:\n  border_fraction: 0.7\n";
  t = ReadReportThresholds(dir / "bad_fraction.yaml");
  ASSERT_FALSE(t.ok());
  EXPECT_NE(t.message().find("border_fraction must be in (0, 0.5)"), std::string::npos)
      << t.message();
  std::ofstream(dir / "bad.yaml") << "intrinsics_report:\n  max_worst_px: -1\n";
  t = ReadReportThresholds(dir / "bad.yaml");
  ASSERT_FALSE(t.ok());
  EXPECT_NE(t.message().find("bad.yaml"), std::string::npos) << t.message();
  EXPECT_NE(t.message().find("max_worst_px"), std::string::npos) << t.message();
}

}  // namespace
}  // namespace groundline::calibration
