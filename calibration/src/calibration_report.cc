#include "groundline/calibration/calibration_report.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numeric>

#include "groundline/calibration/mrcal_cameramodel_io.h"
#include "groundline/calibration/opencv_calibration_io.h"
#include "groundline/calibration/ros_camera_info_io.h"
#include "groundline/core/atomic_file.h"
#include "report_config.h"

namespace groundline::calibration {
namespace {

constexpr const char* kQuadrantNames[4] = {"top-left", "top-right", "bottom-left", "bottom-right"};

std::string Px(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3f px", value);
  return text;
}

}  // namespace

core::Status ReportThresholds::Validate() const {
  if (!(max_rms_px > 0.0)) return core::Status::Error("max_rms_px must be > 0");
  if (!(max_worst_px > 0.0)) return core::Status::Error("max_worst_px must be > 0");
  if (min_corners_per_quadrant < 1) {
    return core::Status::Error("min_corners_per_quadrant must be >= 1");
  }
  return core::Status::Ok();
}

core::Result<ReportThresholds> ReadReportThresholds(const std::filesystem::path& path) {
  ReportThresholds t;
  if (core::Status s =
          internal::ReadConfigSection(path, "intrinsics_report",
                                      {{"max_rms_px", &t.max_rms_px},
                                       {"max_worst_px", &t.max_worst_px},
                                       {"require_all_quadrants", &t.require_all_quadrants},
                                       {"min_corners_per_quadrant", &t.min_corners_per_quadrant}});
      !s.ok()) {
    return s;
  }
  if (core::Status s = t.Validate(); !s.ok()) {
    return core::Status::Error(path.string() + ": key 'intrinsics_report': " + s.message());
  }
  return t;
}

CalibrationReport BuildCalibrationReport(const IntrinsicCalibration& calibration,
                                         const std::string& target_name,
                                         std::vector<RejectedImage> rejected,
                                         const ReportThresholds& thresholds) {
  CalibrationReport report;
  report.target_name = target_name;
  report.thresholds = thresholds;
  report.rejected = std::move(rejected);
  const int w = calibration.camera.width_px();
  const int h = calibration.camera.height_px();
  report.coverage.assign(CalibrationReport::kCoverageCellsX * CalibrationReport::kCoverageCellsY,
                         0);
  for (const ViewResult& v : calibration.views) {
    for (std::size_t j = 0; j < v.observed_px.size(); ++j) {
      if (v.outlier[j]) continue;
      const Eigen::Vector2d& q = v.observed_px[j];
      const int quadrant = (q.x() >= 0.5 * (w - 1) ? 1 : 0) + (q.y() >= 0.5 * (h - 1) ? 2 : 0);
      ++report.quadrant_corners[quadrant];
      const int cx =
          std::clamp(static_cast<int>((q.x() + 0.5) / w * CalibrationReport::kCoverageCellsX), 0,
                     CalibrationReport::kCoverageCellsX - 1);
      const int cy =
          std::clamp(static_cast<int>((q.y() + 0.5) / h * CalibrationReport::kCoverageCellsY), 0,
                     CalibrationReport::kCoverageCellsY - 1);
      ++report.coverage[cy * CalibrationReport::kCoverageCellsX + cx];
    }
  }
  report.views_by_rms.resize(calibration.views.size());
  std::iota(report.views_by_rms.begin(), report.views_by_rms.end(), 0);
  std::stable_sort(report.views_by_rms.begin(), report.views_by_rms.end(), [&](int a, int b) {
    return calibration.views[a].rms_px > calibration.views[b].rms_px;
  });

  const IntrinsicCalibrationSummary& s = calibration.summary;
  if (s.rms_px > thresholds.max_rms_px) {
    report.failures.push_back("RMS " + Px(s.rms_px) + " > " + Px(thresholds.max_rms_px));
    const ViewResult& worst = calibration.views[report.views_by_rms.front()];
    if (worst.rms_px > 2.0 * s.rms_px) {
      report.advice.push_back("drop or retake image " + worst.name + " (its RMS is " +
                              Px(worst.rms_px) + ", the others' much lower)");
    } else {
      report.advice.push_back(
          "the error is spread over all images: check focus and motion blur, that the target "
          "definition matches the print (measure the scale bar), that the board is flat, or try "
          "a richer lens model (--model LENSMODEL_OPENCV8)");
    }
  }
  if (s.worst_px > thresholds.max_worst_px) {
    const ViewResult* worst_view = nullptr;
    for (const ViewResult& v : calibration.views) {
      if (worst_view == nullptr || v.worst_px > worst_view->worst_px) worst_view = &v;
    }
    report.failures.push_back("worst residual " + Px(s.worst_px) + " > " +
                              Px(thresholds.max_worst_px));
    report.advice.push_back("drop or retake image " + worst_view->name +
                            " (it holds the worst corner, " + Px(worst_view->worst_px) +
                            "; look for blur, glare or a misdetected corner)");
  }
  if (thresholds.require_all_quadrants) {
    for (int q = 0; q < 4; ++q) {
      if (report.quadrant_corners[q] >= thresholds.min_corners_per_quadrant) continue;
      report.failures.push_back(std::string(kQuadrantNames[q]) + " quadrant: " +
                                std::to_string(report.quadrant_corners[q]) + " corners < " +
                                std::to_string(thresholds.min_corners_per_quadrant));
      report.advice.push_back(std::string("take more views with the board in the ") +
                              kQuadrantNames[q] + " of the image, close to its corner and edges");
    }
  }
  report.pass = report.failures.empty();
  return report;
}

std::string CalibrationReportJson(const CalibrationReport& report,
                                  const IntrinsicCalibration& calibration) {
  using nlohmann::json;
  const IntrinsicCalibrationSummary& s = calibration.summary;
  json j;
  j["format"] = "groundline-intrinsics-report";
  j["version"] = 1;
  j["verdict"] = report.pass ? "PASS" : "FAIL";
  j["failures"] = report.failures;
  j["advice"] = report.advice;
  j["target"] = report.target_name;
  j["lens_model"] = calibration.camera.lens_model();
  j["intrinsics"] = calibration.camera.intrinsics();
  j["imager_size_px"] = {calibration.camera.width_px(), calibration.camera.height_px()};
  j["error_convention"] =
      "residual r = projected - observed (px); rms_px = sqrt(mean |r|^2) over inlier corners "
      "(per point, 2D vectors); worst_px = max |r|";
  j["rms_px"] = s.rms_px;
  j["worst_px"] = s.worst_px;
  j["corners"] = s.points;
  j["outliers"] = s.outliers;
  j["mrcal_rms_px"] = s.mrcal_rms_px;
  if (s.board_warp_m) j["board_warp_m"] = *s.board_warp_m;
  j["solve_time_s"] = s.solve_time_s;
  j["thresholds"] = {{"max_rms_px", report.thresholds.max_rms_px},
                     {"max_worst_px", report.thresholds.max_worst_px},
                     {"require_all_quadrants", report.thresholds.require_all_quadrants},
                     {"min_corners_per_quadrant", report.thresholds.min_corners_per_quadrant}};
  j["quadrant_corners"] = {{"top_left", report.quadrant_corners[0]},
                           {"top_right", report.quadrant_corners[1]},
                           {"bottom_left", report.quadrant_corners[2]},
                           {"bottom_right", report.quadrant_corners[3]}};
  j["opencv_seed"] = {{"intrinsics", calibration.opencv_seed.intrinsics},
                      {"rms_px", calibration.opencv_seed.rms_px},
                      {"mean_per_view_rms_px", calibration.opencv_seed.mean_per_view_rms_px}};
  json views = json::array();
  for (const ViewResult& v : calibration.views) {
    views.push_back({{"image", v.name},
                     {"corners", v.observed_px.size()},
                     {"inliers", v.inliers},
                     {"rms_px", v.rms_px},
                     {"worst_px", v.worst_px},
                     {"rt_cam_board", v.rt_cam_board}});
  }
  j["views"] = views;
  json worst = json::array();
  for (std::size_t i = 0; i < std::min<std::size_t>(5, report.views_by_rms.size()); ++i) {
    worst.push_back(calibration.views[report.views_by_rms[i]].name);
  }
  j["worst_images"] = worst;
  json rejected = json::array();
  for (const RejectedImage& r : report.rejected) {
    rejected.push_back({{"image", r.name}, {"reason", r.reason}});
  }
  j["rejected_images"] = rejected;
  return j.dump(2) + "\n";
}

core::Status WriteCalibrationOutputs(const std::filesystem::path& out_dir,
                                     const CalibrationReport& report,
                                     const IntrinsicCalibration& calibration) {
  const CameraModel& camera = calibration.camera;
  if (core::Status s = WriteMrcalCameraModel(out_dir / "camera.cameramodel", camera); !s.ok()) {
    return s;
  }
  if (camera.family() != LensFamily::kOther &&
      camera.family() != LensFamily::kSplinedStereographic) {
    if (core::Status s = WriteOpenCvCalibration(out_dir / "camera_opencv.yaml", camera); !s.ok()) {
      return s;
    }
  }
  if (camera.family() == LensFamily::kPinhole || camera.family() == LensFamily::kOpenCv4 ||
      camera.family() == LensFamily::kOpenCv5 || camera.family() == LensFamily::kOpenCv8) {
    if (core::Status s =
            WriteRosCameraInfo(out_dir / "camera_info.yaml", MakeRosCameraInfo(camera, "camera"));
        !s.ok()) {
      return s;
    }
  }
  if (core::Status s = core::WriteFileAtomically(out_dir / "report.json",
                                                 CalibrationReportJson(report, calibration));
      !s.ok()) {
    return s;
  }
  return core::WriteFileAtomically(out_dir / "report.html",
                                   CalibrationReportHtml(report, calibration));
}

}  // namespace groundline::calibration
