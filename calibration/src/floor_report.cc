// floor_report.json and the intrinsics summary it folds in (floor_calibration.h).
#include <nlohmann/json.hpp>

#include <cmath>

#include "floor_report_rows.h"
#include "groundline/calibration/floor_calibration.h"
#include "text_util.h"

namespace groundline::calibration {

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
    s.quadrant_corners = {q.at("top_left").get<int>(), q.at("top_right").get<int>(),
                          q.at("bottom_left").get<int>(), q.at("bottom_right").get<int>()};
  } catch (const nlohmann::json::exception& e) {
    return core::Status::Error(where + ": field '" + field + "': missing or malformed (" +
                               e.what() + ")");
  }
  return s;
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
  if (intrinsics != nullptr) {
    report["intrinsics"] = {
        {"source", intrinsics->source},     {"verdict", intrinsics->pass ? "PASS" : "FAIL"},
        {"failures", intrinsics->failures}, {"advice", intrinsics->advice},
        {"target", intrinsics->target},     {"lens_model", intrinsics->lens_model},
        {"rms_px", intrinsics->rms_px},     {"worst_px", intrinsics->worst_px},
        {"views", intrinsics->views}};
    report["overall_verdict"] = c.pass && intrinsics->pass ? "PASS" : "FAIL";
  }
  return report.dump(2) + "\n";
}

}  // namespace groundline::calibration
