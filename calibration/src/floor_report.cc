// floor_report.json and floor_report.html (floor_calibration.h).
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "groundline/calibration/floor_calibration.h"
#include "groundline/calibration/floor_projection.h"
#include "xml_text.h"

namespace groundline::calibration {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

struct Row {
  const char* key;
  const char* label;
  double scale;  // SI -> technician unit
  const char* unit;
};
constexpr std::array<Row, 6> kRows = {{
    {"height_mm", "height", 1000.0, "mm"},
    {"pitch_deg", "pitch", kRadToDeg, "deg"},
    {"roll_deg", "roll", kRadToDeg, "deg"},
    {"yaw_deg", "yaw", kRadToDeg, "deg"},
    {"forward_mm", "forward offset", 1000.0, "mm"},
    {"lateral_mm", "lateral offset", 1000.0, "mm"},
}};

std::array<double, 6> Values(const CameraMount& m) {
  return {m.height_m, m.pitch_rad, m.roll_rad, m.yaw_rad, m.forward_m, m.lateral_m};
}

std::string Fixed(double v, int digits) {
  std::ostringstream o;
  o.setf(std::ios::fixed);
  o.precision(digits);
  o << v;
  return o.str();
}

}  // namespace

std::string FloorReportJson(const FloorCalibration& c, const FloorCalibrationOptions& options) {
  using nlohmann::json;
  const FloorExtrinsicsResult& s = c.solution;
  json mount = json::object();
  const std::array<double, 6> values = Values(s.mount);
  for (int i = 0; i < 6; ++i) {
    mount[kRows[i].key] = {{"value", values[i] * kRows[i].scale},
                           {"sigma3", 3.0 * std::sqrt(s.covariance(i, i)) * kRows[i].scale}};
  }
  json bev = json::array();
  for (const BevError& e : c.bev) {
    bev.push_back({{"distance_m", e.distance_m}, {"rms_mm", e.rms_mm}, {"sigma3_mm", e.sigma3_mm}});
  }
  json images = json::array();
  for (std::size_t i = 0; i < c.images.size(); ++i) {
    images.push_back({{"name", c.images[i].name},
                      {"corners", c.images[i].corners.size()},
                      {"rms_px", s.image_rms_px[i]}});
  }
  const json report = {
      {"format", "groundline-floor-report"},
      {"version", 1},
      {"verdict", c.verdict},
      {"pass", c.pass},
      {"thresholds",
       {{"max_bev_error_2m_mm", options.max_bev_error_2m_mm},
        {"max_image_rms_px", options.max_image_rms_px}}},
      {"mount", mount},
      {"covariance",
       {{"sigma_px", s.sigma_px},
        {"scaled_by", options.solver.corner_sigma_px > 0.0 ? "stated corner noise"
                                                           : "a posteriori residual variance"}}},
      {"bev_error", bev},
      {"rms_px", s.rms_px},
      {"corners", s.corners},
      {"images", images},
      {"solver",
       {{"iterations", s.iterations},
        {"initial_cost", s.initial_cost},
        {"final_cost", s.final_cost},
        {"termination", s.termination},
        {"time_s", s.solve_time_s}}},
      {"warnings", c.warnings},
  };
  return report.dump(2) + "\n";
}

std::string FloorReportHtml(const FloorCalibration& c, const TagLayout& layout,
                            const CameraModel& camera, const FloorCalibrationOptions& options) {
  const FloorExtrinsicsResult& s = c.solution;
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>groundline floor "
       "calibration</title>\n<style>body{font-family:sans-serif;margin:2em}"
       "table{border-collapse:collapse}td,th{border:1px solid #999;padding:3px 8px;"
       "text-align:right}.pass{color:#070}.fail{color:#b00}</style></head><body>\n"
    << "<h1>Floor calibration: <span class=\"" << (c.pass ? "pass" : "fail") << "\">"
    << internal::XmlEscape(c.verdict) << "</span></h1>\n"
    << "<p>Thresholds: BEV error at 2 m &le; " << options.max_bev_error_2m_mm
    << " mm, corner RMS per image &le; " << options.max_image_rms_px << " px.</p>\n";
  h << "<h2>Camera mount</h2><table><tr><th>parameter</th><th>value</th><th>&plusmn;3&sigma;</th>"
       "<th>unit</th></tr>\n";
  const std::array<double, 6> values = Values(s.mount);
  for (int i = 0; i < 6; ++i) {
    h << "<tr><td>" << kRows[i].label << "</td><td>" << Fixed(values[i] * kRows[i].scale, 3)
      << "</td><td>" << Fixed(3.0 * std::sqrt(s.covariance(i, i)) * kRows[i].scale, 3)
      << "</td><td>" << kRows[i].unit << "</td></tr>\n";
  }
  h << "</table>\n<h2>Expected BEV error on the centre line</h2><table><tr><th>ahead</th>"
       "<th>RMS (1&sigma;)</th><th>3&sigma; worst direction</th></tr>\n";
  for (const BevError& e : c.bev) {
    h << "<tr><td>" << e.distance_m << " m</td><td>" << Fixed(e.rms_mm, 2) << " mm</td><td>"
      << Fixed(e.sigma3_mm, 2) << " mm</td></tr>\n";
  }
  h << "</table>\n<h2>Images</h2><table><tr><th>image</th><th>corners</th><th>RMS px</th></tr>\n";
  for (std::size_t i = 0; i < c.images.size(); ++i) {
    h << "<tr><td>" << internal::XmlEscape(c.images[i].name) << "</td><td>"
      << c.images[i].corners.size() << "</td><td>" << Fixed(s.image_rms_px[i], 3) << "</td></tr>\n";
  }
  h << "</table>\n";
  if (!c.warnings.empty()) {
    h << "<h2>Warnings</h2><ul>\n";
    for (const std::string& w : c.warnings) h << "<li>" << internal::XmlEscape(w) << "</li>\n";
    h << "</ul>\n";
  }

  // The bird's-eye view: floor x up, floor y to the left, as seen from above.
  Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const SurveyedTag& t : layout.tags) {
    for (const Eigen::Vector2d& p : t.CornersInFrame()) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  lo -= Eigen::Vector2d(0.1, 0.1);
  hi += Eigen::Vector2d(0.1, 0.1);
  constexpr double kExaggeration = 20.0;
  const double scale = 800.0 / std::max(hi.y() - lo.y(), hi.x() - lo.x());
  const auto sx = [&](const Eigen::Vector2d& p) { return (hi.y() - p.y()) * scale; };
  const auto sy = [&](const Eigen::Vector2d& p) { return (hi.x() - p.x()) * scale; };
  h << "<h2>Tag field, bird's-eye view</h2><p>Floor frame seen from above (x up, y left). "
       "Green: surveyed tag outlines. Red: detected corners back-projected to the floor "
       "through the solved mount and each image's vehicle pose, their offset from the "
       "surveyed corner drawn "
    << kExaggeration << "&times; enlarged.</p>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\""
    << Fixed((hi.y() - lo.y()) * scale, 0) << "\" height=\"" << Fixed((hi.x() - lo.x()) * scale, 0)
    << "\" style=\"background:#ddd\">\n";
  for (const SurveyedTag& t : layout.tags) {
    h << "<polygon fill=\"#fff\" stroke=\"#080\" stroke-width=\"1.5\" points=\"";
    for (const Eigen::Vector2d& p : t.CornersInFrame())
      h << Fixed(sx(p), 1) << "," << Fixed(sy(p), 1) << " ";
    const Eigen::Vector2d centre = t.T_frame_tag.translation();
    h << "\"/><text x=\"" << Fixed(sx(centre), 1) << "\" y=\"" << Fixed(sy(centre), 1)
      << "\" font-size=\"11\" text-anchor=\"middle\">" << t.id << "</text>\n";
  }
  const FloorProjection projection(camera, s.mount);
  for (const FloorImage& im : c.images) {
    for (const FloorCorner& corner : im.corners) {
      const core::Result<Eigen::Vector2d> base = projection.FloorPointOfPixel(corner.pixel);
      if (!base.ok()) continue;
      const Eigen::Vector2d seen = im.T_floor_base * *base;
      const Eigen::Vector2d drawn = corner.floor_m + kExaggeration * (seen - corner.floor_m);
      h << "<line x1=\"" << Fixed(sx(corner.floor_m), 1) << "\" y1=\""
        << Fixed(sy(corner.floor_m), 1) << "\" x2=\"" << Fixed(sx(drawn), 1) << "\" y2=\""
        << Fixed(sy(drawn), 1) << "\" stroke=\"#c00\"/><circle cx=\"" << Fixed(sx(drawn), 1)
        << "\" cy=\"" << Fixed(sy(drawn), 1) << "\" r=\"1.5\" fill=\"#c00\"/>\n";
    }
  }
  h << "</svg>\n</body></html>\n";
  return h.str();
}

}  // namespace groundline::calibration
