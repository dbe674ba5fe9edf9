#include "groundline/calibration/calibration_report.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numeric>

#include "groundline/calibration/mrcal_cameramodel_io.h"
#include "groundline/calibration/mrcal_optimization_inputs.h"
#include "groundline/calibration/opencv_calibration_io.h"
#include "groundline/calibration/ros_camera_info_io.h"
#include "groundline/core/atomic_file.h"
#include "report_config.h"

namespace groundline::calibration {

core::Status ReportThresholds::Validate() const {
  if (min_views < 3) return core::Status::Error("min_views must be >= 3");
  if (!(max_rms_px > 0.0)) return core::Status::Error("max_rms_px must be > 0");
  if (!(max_worst_px > 0.0)) return core::Status::Error("max_worst_px must be > 0");
  if (min_corners_per_quadrant < 1) {
    return core::Status::Error("min_corners_per_quadrant must be >= 1");
  }
  if (!(border_fraction > 0.0 && border_fraction < 0.5)) {
    return core::Status::Error("border_fraction must be in (0, 0.5)");
  }
  if (min_corners_per_border_zone < 1) {
    return core::Status::Error("min_corners_per_border_zone must be >= 1");
  }
  if (!(min_tilt_deg >= 0.0 && min_tilt_deg < 90.0)) {
    return core::Status::Error("min_tilt_deg must be in [0, 90)");
  }
  if (!(max_projection_uncertainty_px > 0.0)) {
    return core::Status::Error("max_projection_uncertainty_px must be > 0");
  }
  if (!(uncertainty_range_m > 0.0 && uncertainty_range_m <= 100.0)) {
    return core::Status::Error("uncertainty_range_m must be in (0, 100] m");
  }
  if (!(floor_top_fraction >= 0.0 && floor_top_fraction < 1.0)) {
    return core::Status::Error("floor_top_fraction must be in [0, 1)");
  }
  return core::Status::Ok();
}

core::Result<ReportThresholds> ReadReportThresholds(const std::filesystem::path& path) {
  ReportThresholds t;
  if (core::Status s = internal::ReadConfigSection(
          path, "intrinsics_report",
          {{"min_views", &t.min_views},
           {"max_rms_px", &t.max_rms_px},
           {"max_worst_px", &t.max_worst_px},
           {"require_all_quadrants", &t.require_all_quadrants},
           {"min_corners_per_quadrant", &t.min_corners_per_quadrant},
           {"require_border_coverage", &t.require_border_coverage},
           {"border_fraction", &t.border_fraction},
           {"min_corners_per_border_zone", &t.min_corners_per_border_zone},
           {"min_tilt_deg", &t.min_tilt_deg},
           {"max_projection_uncertainty_px", &t.max_projection_uncertainty_px},
           {"uncertainty_range_m", &t.uncertainty_range_m},
           {"floor_top_fraction", &t.floor_top_fraction}});
      !s.ok()) {
    return s;
  }
  if (core::Status s = t.Validate(); !s.ok()) {
    return core::Status::Error(path.string() + ": key 'intrinsics_report': " + s.message());
  }
  return t;
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
  const ReportThresholds& t = report.thresholds;
  j["thresholds"] = {{"min_views", t.min_views},
                     {"max_rms_px", t.max_rms_px},
                     {"max_worst_px", t.max_worst_px},
                     {"require_all_quadrants", t.require_all_quadrants},
                     {"min_corners_per_quadrant", t.min_corners_per_quadrant},
                     {"require_border_coverage", t.require_border_coverage},
                     {"border_fraction", t.border_fraction},
                     {"min_corners_per_border_zone", t.min_corners_per_border_zone},
                     {"min_tilt_deg", t.min_tilt_deg},
                     {"max_projection_uncertainty_px", t.max_projection_uncertainty_px},
                     {"uncertainty_range_m", t.uncertainty_range_m},
                     {"floor_top_fraction", t.floor_top_fraction}};
  j["camera_fingerprint"] = report.camera_fingerprint;
  j["views_count"] = calibration.views.size();
  j["border_corners"] = {
      {"top_left", report.border_corners[0]},  {"top", report.border_corners[1]},
      {"top_right", report.border_corners[2]}, {"left", report.border_corners[3]},
      {"right", report.border_corners[4]},     {"bottom_left", report.border_corners[5]},
      {"bottom", report.border_corners[6]},    {"bottom_right", report.border_corners[7]}};
  j["max_tilt_deg"] = {{"about_vertical", report.max_tilt_about_vertical_deg},
                       {"about_horizontal", report.max_tilt_about_horizontal_deg}};
  j["live_missing"] = report.live_missing;
  if (!report.uncertainty.empty()) {
    json u;
    u["method"] =
        "mrcal projection_uncertainty, mean-frames, finite range: Var(q) = dq/db Var(b) "
        "dq/db', Var(b) = sigma^2 inv(J'J) J_obs' J_obs inv(J'J); figures are the 1-sigma "
        "worst-direction error over the floor rows of the imager; mm are lateral, on a plane "
        "facing the camera at that range";
    u["observed_pixel_sigma_px"] = report.observed_pixel_sigma_px;
    // 1-sigma of each intrinsic parameter (same order as "intrinsics"). The
    // parameters are correlated; the projection figures are the ones to judge.
    std::vector<double> sigma;
    const CalibrationCovariance& cov = *calibration.covariance;
    for (std::size_t k = 0; k < calibration.camera.intrinsics().size(); ++k) {
      const int i = cov.state_index_intrinsics + static_cast<int>(k);
      sigma.push_back(std::sqrt(std::max(0.0, cov.covariance(i, i))));
    }
    j["intrinsics_sigma"] = sigma;
    json ranges = json::array();
    for (const UncertaintyFigure& f : report.uncertainty) {
      ranges.push_back({{"range_m", f.range_m},
                        {"worst_px", f.worst_px},
                        {"worst_mm", f.worst_mm},
                        {"where_px", {f.where_px.x(), f.where_px.y()}},
                        {"cells_not_computable", f.cells_not_computable}});
    }
    u["worst"] = ranges;  // 1, 2, 4 m, then the judged range
    const UncertaintyMap& m = report.uncertainty_map;
    json map_px = json::array();
    for (double v : m.worst_px) map_px.push_back(std::isfinite(v) ? json(v) : json(nullptr));
    u["map"] = {{"range_m", m.range_m},
                {"cells_x", m.cells_x},
                {"cells_y", m.cells_y},
                {"worst_px", map_px}};
    // Var(q) of every cell (xx, xy, yy; px^2, null where not computable) at
    // 1, 2 and 4 m: what the floor report needs to carry the intrinsics'
    // uncertainty to the floor.
    json covariance_maps = json::array();
    for (std::size_t i = 0; i + 1 < report.uncertainty_maps.size(); ++i) {
      const UncertaintyMap& cm = report.uncertainty_maps[i];
      json cells = json::array();
      for (const Eigen::Matrix2d& c : cm.covariance_px2) {
        if (c.allFinite()) {
          cells.push_back({c(0, 0), c(0, 1), c(1, 1)});
        } else {
          cells.push_back(nullptr);
        }
      }
      covariance_maps.push_back({{"range_m", cm.range_m},
                                 {"cells_x", cm.cells_x},
                                 {"cells_y", cm.cells_y},
                                 {"covariance_px2", cells}});
    }
    u["covariance_maps"] = covariance_maps;
    j["projection_uncertainty"] = u;
  } else {
    j["projection_uncertainty"] = {{"error", calibration.covariance_error}};
  }
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
  if (core::Status s = WriteMrcalCameraModel(out_dir / "camera.cameramodel", camera, {},
                                             MrcalOptimizationInputsBase85(calibration));
      !s.ok()) {
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
