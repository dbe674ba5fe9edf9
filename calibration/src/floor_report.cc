// floor_report.json and the intrinsics summary it folds in (floor_calibration.h).
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

#include "floor_report_rows.h"
#include "groundline/core/json_fields.h"
#include "groundline/calibration/calibration_report.h"
#include "groundline/calibration/floor_calibration.h"
#include "text_util.h"

namespace groundline::calibration {
namespace {

// An int field (core::JsonInteger: no unchecked cast), else the walk's exception.
int IntegerOf(const nlohmann::json& v) {
  const std::optional<std::int64_t> i = core::JsonInteger(v, -2147483648LL, 2147483647LL);
  if (!i) throw nlohmann::json::other_error::create(501, "expected an integer within int range", &v);
  return static_cast<int>(*i);
}

}  // namespace

core::Result<IntrinsicsReportSummary> ReadIntrinsicsReportSummary(
    const std::filesystem::path& report_json) {
  core::Result<std::string> text = text_util::ReadTextFile(report_json, "intrinsics report");
  if (!text.ok()) return text.status();
  const std::string where = report_json.string();
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(*text);
  } catch (const nlohmann::json::exception& e) {
    return core::Status::Error(where + ": not JSON (" + e.what() + ")");
  }
  // json::value() throws for a 'format' that is not a string: look it up instead.
  const auto format = j.is_object() ? j.find("format") : j.end();
  if (format == j.end() || !format->is_string() ||
      format->get<std::string>() != "groundline-intrinsics-report") {
    return core::Status::Error(where +
                               ": field 'format': expected \"groundline-intrinsics-report\" "
                               "(the report.json of `groundline calibrate intrinsics`)");
  }
  IntrinsicsReportSummary s;
  s.source = where;
  const char* field = "verdict";
  try {
    s.pass = j.at("verdict").get<std::string>() == "PASS";
    field = "failures";
    s.failures = j.at(field).get<std::vector<std::string>>();
    field = "advice";
    s.advice = j.at(field).get<std::vector<std::string>>();
    field = "target";
    s.target = j.at(field).get<std::string>();
    field = "lens_model";
    s.lens_model = j.at(field).get<std::string>();
    field = "rms_px";
    s.rms_px = j.at(field).get<double>();
    field = "worst_px";
    s.worst_px = j.at(field).get<double>();
    field = "views";
    s.views = static_cast<int>(j.at(field).size());
    field = "quadrant_corners";
    const nlohmann::json& q = j.at(field);
    s.quadrant_corners = {IntegerOf(q.at("top_left")), IntegerOf(q.at("top_right")),
                          IntegerOf(q.at("bottom_left")), IntegerOf(q.at("bottom_right"))};
    field = "imager_size_px";
    const nlohmann::json& size = j.at(field);
    if (!size.is_array() || size.size() != 2) {
      throw nlohmann::json::other_error::create(501, "expected [width, height]", &size);
    }
    s.imager_size_px = {IntegerOf(size[0]), IntegerOf(size[1])};
    field = "intrinsics";
    s.intrinsics = j.at(field).get<std::vector<double>>();
    field = "camera_fingerprint";
    s.camera_fingerprint = j.value(field, "");
    field = "projection_uncertainty";
    if (j.contains(field) && j.at(field).contains("covariance_maps")) {
      for (const nlohmann::json& m : j.at(field).at("covariance_maps")) {
        IntrinsicsReportSummary::CovarianceMap map;
        map.range_m = m.at("range_m").get<double>();
        map.cells_x = IntegerOf(m.at("cells_x"));
        map.cells_y = IntegerOf(m.at("cells_y"));
        for (const nlohmann::json& c : m.at("covariance_px2")) {
          Eigen::Matrix2d v = Eigen::Matrix2d::Constant(std::nan(""));
          if (!c.is_null()) {
            const std::array<double, 3> xy = c.get<std::array<double, 3>>();
            v << xy[0], xy[1], xy[1], xy[2];
          }
          map.covariance_px2.push_back(v);
        }
        if (map.cells_x < 1 || map.cells_y < 1 ||
            map.covariance_px2.size() != static_cast<std::size_t>(map.cells_x) * map.cells_y) {
          throw nlohmann::json::other_error::create(501, "covariance map size mismatch", &m);
        }
        s.covariance_maps.push_back(std::move(map));
      }
      std::sort(s.covariance_maps.begin(), s.covariance_maps.end(),
                [](const auto& a, const auto& b) { return a.range_m < b.range_m; });
    }
    if (j.contains(field) && j.at(field).contains("worst")) {
      const nlohmann::json& worst = j.at(field).at("worst");
      for (std::size_t i = 0; i + 1 < worst.size(); ++i) {
        s.projection_uncertainty.push_back({worst[i].at("range_m").get<double>(),
                                            worst[i].at("worst_px").get<double>(),
                                            worst[i].at("worst_mm").get<double>()});
      }
    }
  } catch (const nlohmann::json::exception& e) {
    const std::string f = field;
    const bool newer = f == "imager_size_px" || f == "intrinsics";
    return core::Status::Error(where + ": field '" + f + "': missing or malformed (" + e.what() +
                               ")" +
                               (newer ? "; the camera check needs it: rerun `groundline calibrate "
                                        "intrinsics` to write a current report"
                                      : ""));
  }
  return s;
}

core::Status CheckSameCamera(const IntrinsicsReportSummary& report, const CameraModel& camera,
                             const std::string& camera_source) {
  const std::string head = "--intrinsics-report " + report.source + " and --camera " +
                           camera_source + " are not the same camera: ";
  const std::string todo =
      "; pass the report.json written by `groundline calibrate intrinsics` together with the "
      ".cameramodel it wrote (the commissioning report must judge the camera that is mounted)";
  const std::array<int, 2> size = {camera.width_px(), camera.height_px()};
  if (report.imager_size_px != size) {
    return core::Status::Error(
        head + "the report is for a " + std::to_string(report.imager_size_px[0]) + "x" +
        std::to_string(report.imager_size_px[1]) + " px imager, the camera model is " +
        std::to_string(size[0]) + "x" + std::to_string(size[1]) + " px" + todo);
  }
  if (report.lens_model != camera.lens_model()) {
    return core::Status::Error(head + "lens model " + report.lens_model + " in the report, " +
                               camera.lens_model() + " in the camera model" + todo);
  }
  if (!report.camera_fingerprint.empty()) {
    const std::string fingerprint = CameraFingerprint(camera);
    if (report.camera_fingerprint != fingerprint) {
      return core::Status::Error(head + "model fingerprint " + report.camera_fingerprint +
                                 " in the report, " + fingerprint +
                                 " for the camera model (different intrinsics)" + todo);
    }
    return core::Status::Ok();
  }
  const std::vector<double>& q = camera.intrinsics();
  bool same = report.intrinsics.size() == q.size();
  for (std::size_t i = 0; same && i < q.size(); ++i) {
    same = std::abs(report.intrinsics[i] - q[i]) <= 1e-9 * std::max(1.0, std::abs(q[i]));
  }
  if (!same) return core::Status::Error(head + "the intrinsics differ" + todo);
  return core::Status::Ok();
}

std::string FloorReportJson(const FloorCalibration& c, const FloorCalibrationOptions& options,
                            const IntrinsicsReportSummary* intrinsics) {
  using nlohmann::json;
  const FloorExtrinsicsResult& s = c.solution;
  json mount = json::object();
  const std::array<double, 6> values = internal::MountValues(s.mount);
  for (int i = 0; i < 6; ++i) {
    const internal::MountRow& row = internal::kMountRows[i];
    const double sigma3 = 3.0 * std::sqrt(s.covariance(i, i)) * row.scale;
    const double value = values[i] * row.scale;
    mount[row.key] = {{"value", value},
                      {"sigma3", sigma3},
                      {"lower_3sigma", value - sigma3},
                      {"upper_3sigma", value + sigma3}};
  }
  json bev = json::array();
  for (const BevError& e : c.bev) {
    bev.push_back({{"distance_m", e.distance_m}, {"rms_mm", e.rms_mm}, {"sigma3_mm", e.sigma3_mm}});
  }
  json images = json::array();
  for (std::size_t i = 0; i < c.images.size(); ++i) {
    images.push_back(
        {{"name", c.images[i].name},
         {"corners", c.images[i].corners.size()},
         {"rms_px", s.image_rms_px[i]},
         {"rms_checked_px",
          c.image_rms_checked_px.size() > i ? c.image_rms_checked_px[i] : s.image_rms_px[i]}});
  }
  json tags = json::array();
  for (const TagResidual& t : c.tags) {
    tags.push_back({{"id", t.id}, {"images", t.images}, {"rms_px", t.rms_px}});
  }
  const FloorReportThresholds& t = c.thresholds;
  json report = {
      {"format", "groundline-floor-report"},
      {"version", 2},
      {"verdict", c.pass ? "PASS" : "FAIL"},
      {"pass", c.pass},
      {"failures", c.failures},
      {"advice", c.advice},
      {"thresholds",
       {{"max_bev_error_2m_mm", t.max_bev_error_2m_mm},
        {"max_image_rms_px", t.max_image_rms_px},
        {"max_tag_rms_px", t.max_tag_rms_px},
        {"require_all_quadrants", t.require_all_quadrants},
        {"min_corners_per_quadrant", t.min_corners_per_quadrant}}},
      {"mount", mount},
      {"covariance",
       {{"sigma_px", s.sigma_px},
        {"a_posteriori_sigma_px", s.a_posteriori_sigma_px},
        {"min_corner_sigma_px",
         options.solver.corner_sigma_px > 0.0 ? 0.0 : options.solver.min_corner_sigma_px},
        {"scaled_by", internal::CovarianceScaleText(c, options)},
        {"survey_sigma_mm", 1000.0 * s.survey_sigma_m},
        {"matrix_si", std::vector<double>(s.covariance.data(), s.covariance.data() + 36)}}},
      {"bev_error", bev},
      {"rms_px", s.rms_px},
      {"corners", s.corners},
      {"gated_corners", s.gated_corners},
      {"quadrant_corners",
       {{"top_left", c.quadrant_corners[0]},
        {"top_right", c.quadrant_corners[1]},
        {"bottom_left", c.quadrant_corners[2]},
        {"bottom_right", c.quadrant_corners[3]}}},
      {"images", images},
      {"tags", tags},
      {"solver",
       {{"iterations", s.iterations},
        {"initial_cost", s.initial_cost},
        {"final_cost", s.final_cost},
        {"termination", s.termination},
        {"time_s", s.solve_time_s}}},
      {"warnings", c.warnings},
  };
  if (!c.rectified.grey.empty()) {
    report["rectified_floor"] = {{"resolution_m", c.rectified.resolution_m},
                                 {"width_px", c.rectified.width_px},
                                 {"height_px", c.rectified.height_px},
                                 {"x_max_m", c.rectified.max_corner_m.x()},
                                 {"y_max_m", c.rectified.max_corner_m.y()}};
  }
  if (!c.bev_map.covariance_m2.empty()) {
    // Per cell, sqrt(trace) of the floor covariance in mm (bev_uncertainty.json
    // holds the covariances themselves).
    json rms = json::array();
    for (const Eigen::Matrix2d& m : c.bev_map.covariance_m2) {
      if (m.allFinite()) {
        rms.push_back(std::round(1e4 * std::sqrt(m.trace())) / 10.0);
      } else {
        rms.push_back(nullptr);
      }
    }
    report["bev_uncertainty"] = {{"file", "bev_uncertainty.json"},
                                 {"includes_intrinsics", c.bev_map.includes_intrinsics},
                                 {"x0_m", c.bev_map.x0_m},
                                 {"y0_m", c.bev_map.y0_m},
                                 {"cell_m", c.bev_map.cell_m},
                                 {"cells_x", c.bev_map.cells_x},
                                 {"cells_y", c.bev_map.cells_y},
                                 {"worst_rms_mm", c.bev_map.WorstRmsMm()},
                                 {"rms_mm", rms}};
  }
  if (intrinsics != nullptr) {
    report["intrinsics"] = {
        {"source", intrinsics->source},     {"verdict", intrinsics->pass ? "PASS" : "FAIL"},
        {"failures", intrinsics->failures}, {"advice", intrinsics->advice},
        {"target", intrinsics->target},     {"lens_model", intrinsics->lens_model},
        {"rms_px", intrinsics->rms_px},     {"worst_px", intrinsics->worst_px},
        {"views", intrinsics->views},       {"camera_fingerprint", intrinsics->camera_fingerprint}};
    json uncertainty = json::array();
    for (const std::array<double, 3>& u : intrinsics->projection_uncertainty) {
      uncertainty.push_back({{"range_m", u[0]}, {"worst_px", u[1]}, {"worst_mm", u[2]}});
    }
    report["intrinsics"]["projection_uncertainty"] = uncertainty;
    report["overall_verdict"] = c.pass && intrinsics->pass ? "PASS" : "FAIL";
    json budget = json::array();
    for (const BevErrorBudget& b : c.bev_budget) {
      budget.push_back({{"distance_m", b.distance_m},
                        {"known", b.known},
                        {"pixel", {b.pixel.x(), b.pixel.y()}},
                        {"range_m", b.range_m},
                        {"extrinsics_rms_mm", b.extrinsics_rms_mm},
                        {"intrinsics_rms_mm", b.intrinsics_rms_mm},
                        {"total_rms_mm", b.total_rms_mm},
                        {"total_sigma3_mm", b.total_sigma3_mm}});
    }
    report["bev_error_budget"] = budget;
  }
  return report.dump(2) + "\n";
}

}  // namespace groundline::calibration
