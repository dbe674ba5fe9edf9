// floor_report.html (floor_calibration.h): one self-contained page.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "floor_report_rows.h"
#include "groundline/calibration/floor_calibration.h"
#include "groundline/calibration/floor_projection.h"
#include "png_data_uri.h"
#include "xml_text.h"

namespace groundline::calibration {
namespace {

using internal::XmlEscape;

constexpr const char* kStyle =
    "<style>body{font-family:sans-serif;margin:24px;max-width:1000px}"
    "table{border-collapse:collapse;margin-bottom:8px}td,th{border:1px solid #ccc;padding:3px "
    "8px;text-align:right}th{background:#eee}td.l,th:first-child{text-align:left}"
    ".pass{color:#fff;background:#2e7d32;padding:4px 12px}"
    ".fail{color:#fff;background:#c62828;padding:4px 12px}.bad{color:#c62828;font-weight:bold}"
    "</style>";

std::string Fixed(double v, int digits) {
  std::ostringstream o;
  o.setf(std::ios::fixed);
  o.precision(digits);
  o << v;
  return o.str();
}

std::string Badge(bool pass) {
  return pass ? "<span class='pass'>PASS</span>" : "<span class='fail'>FAIL</span>";
}

void FailuresAndAdvice(const std::vector<std::string>& failures,
                       const std::vector<std::string>& advice, std::ostringstream& h) {
  if (failures.empty()) return;
  h << "<h3>What failed and what to do</h3><ul>";
  for (const std::string& f : failures) h << "<li class='bad'>" << XmlEscape(f) << "</li>";
  for (const std::string& a : advice) h << "<li>" << XmlEscape(a) << "</li>";
  h << "</ul>\n";
}

void IntrinsicsSection(const IntrinsicsReportSummary& s, std::ostringstream& h) {
  h << "<h2>1. Intrinsics " << Badge(s.pass) << "</h2><p>From <code>" << XmlEscape(s.source)
    << "</code> (full report: report.html next to it). Target <b>" << XmlEscape(s.target)
    << "</b>, lens model <b>" << XmlEscape(s.lens_model) << "</b>, " << s.views
    << " views.</p><table><tr><th>figure</th><th>value</th></tr><tr><td class='l'>RMS</td><td>"
    << Fixed(s.rms_px, 4) << " px</td></tr><tr><td class='l'>worst residual</td><td>"
    << Fixed(s.worst_px, 4) << " px</td></tr><tr><td class='l'>corners per image quadrant "
    << "(TL TR BL BR)</td><td>" << s.quadrant_corners[0] << " " << s.quadrant_corners[1] << " "
    << s.quadrant_corners[2] << " " << s.quadrant_corners[3] << "</td></tr>";
  for (const std::array<double, 3>& u : s.projection_uncertainty) {
    h << "<tr><td class='l'>projection uncertainty at " << Fixed(u[0], 0)
      << " m (worst, 1&sigma;)</td><td>" << Fixed(u[1], 3) << " px, " << Fixed(u[2], 2)
      << " mm face on</td></tr>";
  }
  h << "</table><p>Camera fingerprint " << XmlEscape(s.camera_fingerprint)
    << " (the same as --camera's).</p>\n";
  FailuresAndAdvice(s.failures, s.advice, h);
}

// The rectified floor with the surveyed outlines over it, in raster pixels.
void RectifiedSection(const FloorCalibration& c, const TagLayout& layout, std::ostringstream& h) {
  const FloorRaster& r = c.rectified;
  const std::string uri = internal::GreyPngDataUri(r.grey, r.width_px, r.height_px);
  if (uri.empty()) return;
  const double shown = std::min(900.0, static_cast<double>(r.width_px));
  h << "<h3>Rectified floor with the surveyed tag outlines</h3><p>The images warped onto the "
       "floor plane with the solved mount and each image's vehicle pose, seen from above "
       "(floor x up, y left; "
    << Fixed(1000.0 * r.resolution_m, 1)
    << " mm per pixel; black: seen by no image). Green: the surveyed outline of each tag's black "
       "square, with its id. With a good mount every black square fills its outline; a "
       "square shifted or turned against its outline points at that tag's survey or at the "
       "mount.";
  std::string left_out;
  for (std::size_t i = 0; i < c.images.size(); ++i) {
    if (i < c.image_failed.size() && c.image_failed[i]) left_out += " " + c.images[i].name;
  }
  if (!left_out.empty()) h << " Left out (failed their check):" << XmlEscape(left_out) << ".";
  h << "</p>\n";
  // Below the raster, a strip for the ids of the nearest row and the scale bar.
  const double font = std::max(10.0, 0.05 / r.resolution_m);
  const double total_height = r.height_px + 2.5 * font;
  h << "<svg xmlns='http://www.w3.org/2000/svg' viewBox='0 0 " << r.width_px << " "
    << Fixed(total_height, 0) << "' width='" << Fixed(shown, 0) << "' height='"
    << Fixed(shown * total_height / r.width_px, 0) << "'><image width='" << r.width_px
    << "' height='" << r.height_px << "' href='" << uri << "'/>\n";
  for (const SurveyedTag& t : layout.tags) {
    h << "<polygon fill='none' stroke='#00e676' stroke-width='2' "
         "vector-effect='non-scaling-stroke' points='";
    for (const Eigen::Vector2d& p : t.CornersInFrame()) {
      const Eigen::Vector2d q = r.RasterOfFloor(p);
      h << Fixed(q.x(), 1) << "," << Fixed(q.y(), 1) << " ";
    }
    // The id below the tag on the page, clear of its outline and white ring.
    const Eigen::Vector2d centre = r.RasterOfFloor(t.T_frame_tag.translation());
    double below = 0.0;
    for (const Eigen::Vector2d& p : t.CornersInFrame()) {
      below = std::max(below, r.RasterOfFloor(p).y() - centre.y());
    }
    h << "'/><text x='" << Fixed(centre.x(), 1) << "' y='"
      << Fixed(centre.y() + below + 0.15 * t.size_m / r.resolution_m + 0.8 * font, 1)
      << "' font-size='" << Fixed(font, 0)
      << "' font-family='sans-serif' font-weight='bold' fill='#00e676' stroke='#000' "
         "stroke-width='3' paint-order='stroke' text-anchor='middle'>"
      << t.id << "</text>\n";
  }
  const double bar_px = 0.5 / r.resolution_m;
  const double bar_y = total_height - 0.9 * font;
  h << "<rect x='" << Fixed(r.width_px - bar_px - 4.0 * font, 1) << "' y='" << Fixed(bar_y, 1)
    << "' width='" << Fixed(bar_px, 1) << "' height='" << Fixed(0.4 * font, 1)
    << "' fill='#000'/><text x='" << Fixed(r.width_px - 0.5 * font, 1) << "' y='"
    << Fixed(bar_y + 0.4 * font, 1) << "' font-size='" << Fixed(font, 0)
    << "' font-family='sans-serif' text-anchor='end'>0.5 m</text></svg>\n";
}

// The detected corners back-projected to the floor, offsets enlarged.
void BackProjectedSection(const FloorCalibration& c, const TagLayout& layout,
                          const CameraModel& camera, std::ostringstream& h) {
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
  h << "<h3>Corner offsets on the floor</h3><p>Green: surveyed tag outlines. Red: detected "
       "corners back-projected to the floor through the solved mount and each image's vehicle "
       "pose (images that failed their check left out), their offset from the surveyed corner "
       "drawn "
    << kExaggeration << "&times; enlarged.</p>\n<svg xmlns='http://www.w3.org/2000/svg' width='"
    << Fixed((hi.y() - lo.y()) * scale, 0) << "' height='" << Fixed((hi.x() - lo.x()) * scale, 0)
    << "' style='background:#ddd'>\n";
  for (const SurveyedTag& t : layout.tags) {
    h << "<polygon fill='#fff' stroke='#080' stroke-width='1.5' points='";
    for (const Eigen::Vector2d& p : t.CornersInFrame())
      h << Fixed(sx(p), 1) << "," << Fixed(sy(p), 1) << " ";
    const Eigen::Vector2d centre = t.T_frame_tag.translation();
    h << "'/><text x='" << Fixed(sx(centre), 1) << "' y='" << Fixed(sy(centre), 1)
      << "' font-size='11' text-anchor='middle'>" << t.id << "</text>\n";
  }
  const FloorProjection projection(camera, c.solution.mount);
  for (std::size_t i = 0; i < c.images.size(); ++i) {
    if (i < c.image_failed.size() && c.image_failed[i]) continue;
    const FloorImage& im = c.images[i];
    for (const FloorCorner& corner : im.corners) {
      const core::Result<Eigen::Vector2d> base = projection.FloorPointOfPixel(corner.pixel);
      if (!base.ok()) continue;
      const Eigen::Vector2d seen = im.T_floor_base * *base;
      const Eigen::Vector2d drawn = corner.floor_m + kExaggeration * (seen - corner.floor_m);
      h << "<line x1='" << Fixed(sx(corner.floor_m), 1) << "' y1='" << Fixed(sy(corner.floor_m), 1)
        << "' x2='" << Fixed(sx(drawn), 1) << "' y2='" << Fixed(sy(drawn), 1)
        << "' stroke='#c00'/><circle cx='" << Fixed(sx(drawn), 1) << "' cy='" << Fixed(sy(drawn), 1)
        << "' r='1.5' fill='#c00'/>\n";
    }
  }
  h << "</svg>\n";
}


// The BEV uncertainty map as an SVG grid seen from above the vehicle: ahead
// up, left to the left; each cell coloured by its RMS (viridis, 0 to the
// worst cell) with the figure in mm, grey where the camera does not see it.
void BevUncertaintySection(const FloorCalibration& c, std::ostringstream& h) {
  const BevUncertaintyMap& m = c.bev_map;
  if (m.covariance_m2.empty()) return;
  const double worst = std::max(m.WorstRmsMm(), 1e-9);
  cv::Mat ramp(1, 256, CV_8UC1), colours;
  for (int i = 0; i < 256; ++i) ramp.at<unsigned char>(0, i) = static_cast<unsigned char>(i);
  cv::applyColorMap(ramp, colours, cv::COLORMAP_VIRIDIS);
  const auto colour = [&](double rms_mm) {
    const int k = std::clamp(static_cast<int>(std::lround(255.0 * rms_mm / worst)), 0, 255);
    const cv::Vec3b bgr = colours.at<cv::Vec3b>(0, k);
    char hex[8];
    std::snprintf(hex, sizeof hex, "#%02x%02x%02x", bgr[2], bgr[1], bgr[0]);
    return std::string(hex);
  };
  constexpr int kCell = 30, kLeft = 52, kTop = 10;
  const int w = kLeft + m.cells_y * kCell + 10, hgt = kTop + m.cells_x * kCell + 40;
  h << "<h3>BEV uncertainty map</h3><p>The floor position error (1&sigma; RMS, mm) that the "
       "calibration leaves in each " << Fixed(m.cell_m * 100.0, 0) << " cm cell of the "
       "bird's-eye view: the mount's covariance"
    << (m.includes_intrinsics ? " and the intrinsics' projection uncertainty" : "")
    << ", seen from above the vehicle (ahead up, left to the left). Worst cell "
    << Fixed(m.WorstRmsMm(), 2) << " mm; grey: not seen by the camera. Perception uses "
       "bev_uncertainty.json as the floor of its line covariances.";
  if (!m.includes_intrinsics) {
    h << " Without --intrinsics-report the intrinsics' part is not in.";
  }
  h << "</p>\n<svg xmlns='http://www.w3.org/2000/svg' width='" << w << "' height='" << hgt
    << "' font-family='sans-serif' font-size='9'>\n";
  for (int ix = 0; ix < m.cells_x; ++ix) {
    const int y_px = kTop + (m.cells_x - 1 - ix) * kCell;
    for (int iy = 0; iy < m.cells_y; ++iy) {
      const int x_px = kLeft + (m.cells_y - 1 - iy) * kCell;
      const Eigen::Matrix2d& cov = m.covariance_m2[static_cast<std::size_t>(iy) * m.cells_x + ix];
      const bool known = cov.allFinite();
      const double rms = known ? 1000.0 * std::sqrt(std::max(0.0, cov.trace())) : 0.0;
      h << "<rect x='" << x_px << "' y='" << y_px << "' width='" << kCell << "' height='" << kCell
        << "' fill='" << (known ? colour(rms) : std::string("#bbbbbb")) << "' stroke='#fff'/>";
      if (known) {
        h << "<text x='" << x_px + kCell / 2 << "' y='" << y_px + kCell / 2 + 3
          << "' text-anchor='middle' fill='" << (rms > 0.6 * worst ? "#000" : "#fff") << "'>"
          << Fixed(rms, rms < 1.0 ? 2 : rms < 10.0 ? 1 : 0) << "</text>";
      }
    }
    h << "\n";
    if (ix % 5 == 0) {
      h << "<text x='" << kLeft - 4 << "' y='" << y_px + kCell << "' text-anchor='end'>"
        << Fixed(m.x0_m + ix * m.cell_m, 1) << " m</text>\n";
    }
  }
  const int bottom = kTop + m.cells_x * kCell;
  for (int iy = 0; iy <= m.cells_y; iy += 5) {
    h << "<text x='" << kLeft + (m.cells_y - iy) * kCell << "' y='" << bottom + 14
      << "' text-anchor='middle'>" << Fixed(m.y0_m + iy * m.cell_m, 1) << "</text>";
  }
  h << "<text x='" << kLeft + m.cells_y * kCell / 2 << "' y='" << bottom + 30
    << "' text-anchor='middle'>y (m, left positive); rows: x ahead of base_link</text></svg>\n";
}

}  // namespace

std::string FloorReportHtml(const FloorCalibration& c, const TagLayout& layout,
                            const CameraModel& camera, const FloorCalibrationOptions& options,
                            const IntrinsicsReportSummary* intrinsics) {
  const FloorExtrinsicsResult& s = c.solution;
  const FloorReportThresholds& t = c.thresholds;
  std::ostringstream h;
  h << "<!DOCTYPE html><html><head><meta charset='utf-8'><title>groundline commissioning "
       "report</title>"
    << kStyle << "</head><body>\n";
  if (intrinsics != nullptr) {
    h << "<h1>Camera commissioning " << Badge(c.pass && intrinsics->pass) << "</h1>\n";
    IntrinsicsSection(*intrinsics, h);
    h << "<h2>2. Floor extrinsics " << Badge(c.pass) << "</h2>\n";
  } else {
    h << "<h1>Floor calibration " << Badge(c.pass) << "</h1>\n";
  }
  h << "<p>" << c.images.size() << " images, " << s.corners << " tag corners, " << c.tags.size()
    << " tags seen, corner RMS " << Fixed(s.rms_px, 3) << " px";
  if (s.gated_corners > 0) {
    h << " (" << s.gated_corners << " corners far off the initial mount left out of the solve)";
  }
  h << ".</p>\n";
  const std::vector<double>& checked =
      c.image_rms_checked_px.size() == c.images.size() ? c.image_rms_checked_px : s.image_rms_px;
  double worst_image = 0.0;
  for (double v : checked) worst_image = std::max(worst_image, v);
  const double worst_tag = c.tags.empty() ? 0.0 : c.tags.front().rms_px;
  const int fewest = *std::min_element(c.quadrant_corners.begin(), c.quadrant_corners.end());
  const auto row = [&](const char* what, const std::string& value, const std::string& limit,
                       bool ok) {
    h << "<tr><td class='l'>" << what << "</td><td" << (ok ? "" : " class='bad'") << ">" << value
      << "</td><td>" << limit << "</td></tr>";
  };
  h << "<table><tr><th>check</th><th>value</th><th>limit</th></tr>";
  row("BEV error 2 m ahead (1&sigma;)", Fixed(c.bev[1].rms_mm, 2) + " mm",
      "&le; " + Fixed(t.max_bev_error_2m_mm, 2) + " mm", c.bev[1].rms_mm <= t.max_bev_error_2m_mm);
  row("worst image corner RMS (tags that pass)", Fixed(worst_image, 3) + " px",
      "&le; " + Fixed(t.max_image_rms_px, 3) + " px", worst_image <= t.max_image_rms_px);
  row("worst tag corner RMS", Fixed(worst_tag, 3) + " px",
      "&le; " + Fixed(t.max_tag_rms_px, 3) + " px", worst_tag <= t.max_tag_rms_px);
  row("fewest tag corners in an image quadrant", std::to_string(fewest),
      t.require_all_quadrants ? "&ge; " + std::to_string(t.min_corners_per_quadrant)
                              : "not checked",
      !t.require_all_quadrants || fewest >= t.min_corners_per_quadrant);
  h << "</table>\n";
  FailuresAndAdvice(c.failures, c.advice, h);

  h << "<h3>Camera mount</h3><table><tr><th>parameter</th><th>value</th><th>&plusmn;3&sigma;</th>"
       "<th>3&sigma; range</th><th>unit</th></tr>\n";
  const std::array<double, 6> values = internal::MountValues(s.mount);
  for (int i = 0; i < 6; ++i) {
    const internal::MountRow& m = internal::kMountRows[i];
    const int digits = m.scale > 100.0 ? 2 : 4;
    const double v = values[i] * m.scale, b = 3.0 * std::sqrt(s.covariance(i, i)) * m.scale;
    h << "<tr><td class='l'>" << m.label << "</td><td>" << Fixed(v, digits) << "</td><td>"
      << Fixed(b, digits) << "</td><td>" << Fixed(v - b, digits) << " &hellip; "
      << Fixed(v + b, digits) << "</td><td class='l'>" << m.unit << "</td></tr>\n";
  }
  h << "</table><p>Covariance scaled by a corner noise of " << Fixed(s.sigma_px, 3) << " px ("
    << XmlEscape(internal::CovarianceScaleText(c, options)) << "; the residuals alone say "
    << Fixed(s.a_posteriori_sigma_px, 3) << " px).</p>\n";
  h << "<h3>Expected BEV error on the centre line</h3><table><tr><th>ahead</th>"
       "<th>RMS (1&sigma;)</th><th>3&sigma;, worst direction</th></tr>\n";
  for (const BevError& e : c.bev) {
    h << "<tr><td>" << Fixed(e.distance_m, 0) << " m</td><td>" << Fixed(e.rms_mm, 2)
      << " mm</td><td>" << Fixed(e.sigma3_mm, 2) << " mm</td></tr>\n";
  }
  h << "</table>\n";
  if (!c.bev_budget.empty()) {
    h << "<h3>BEV error budget: mount and intrinsics</h3><p>The floor position error (1&sigma; "
         "RMS) at each BEV point from the mount's covariance and from the intrinsics' projection "
         "uncertainty (the intrinsics report's map, carried to the floor through this mount); "
         "the two are independent and add.</p><table><tr><th>ahead</th><th>seen at pixel</th>"
         "<th>range</th><th>mount</th><th>intrinsics</th><th>both</th><th>both, 3&sigma; worst "
         "direction</th></tr>\n";
    for (const BevErrorBudget& b : c.bev_budget) {
      h << "<tr><td>" << Fixed(b.distance_m, 0) << " m</td>";
      if (!b.known) {
        h << "<td colspan='6' class='l'>not known (the point is off the image, or the "
             "intrinsics report has no uncertainty there)</td></tr>\n";
        continue;
      }
      h << "<td>" << Fixed(b.pixel.x(), 0) << ", " << Fixed(b.pixel.y(), 0) << "</td><td>"
        << Fixed(b.range_m, 2) << " m</td><td>" << Fixed(b.extrinsics_rms_mm, 2) << " mm</td><td>"
        << Fixed(b.intrinsics_rms_mm, 2) << " mm</td><td>" << Fixed(b.total_rms_mm, 2)
        << " mm</td><td>" << Fixed(b.total_sigma3_mm, 2) << " mm</td></tr>\n";
    }
    h << "</table>\n";
  }
  BevUncertaintySection(c, h);
  if (!c.rectified.grey.empty()) RectifiedSection(c, layout, h);
  BackProjectedSection(c, layout, camera, h);

  h << "<h3>Images</h3><table><tr><th>image</th><th>corners</th><th>RMS px, all corners</th>"
       "<th>RMS px, tags that pass</th></tr>\n";
  for (std::size_t i = 0; i < c.images.size(); ++i) {
    const bool ok = checked[i] <= t.max_image_rms_px;
    h << "<tr><td class='l'>" << XmlEscape(c.images[i].name) << "</td><td>"
      << c.images[i].corners.size() << "</td><td>" << Fixed(s.image_rms_px[i], 3) << "</td><td"
      << (ok ? "" : " class='bad'") << ">" << Fixed(checked[i], 3) << "</td></tr>\n";
  }
  h << "</table><p>Tag corners per image quadrant (TL TR BL BR), all images: "
    << c.quadrant_corners[0] << " " << c.quadrant_corners[1] << " " << c.quadrant_corners[2] << " "
    << c.quadrant_corners[3] << ".</p>\n<h3>Tags (worst first)</h3><table><tr><th>tag</th>"
    << "<th>images</th><th>RMS px</th></tr>\n";
  for (const TagResidual& tag : c.tags) {
    h << "<tr><td>" << tag.id << "</td><td>" << tag.images << "</td><td"
      << (tag.rms_px <= t.max_tag_rms_px ? "" : " class='bad'") << ">" << Fixed(tag.rms_px, 3)
      << "</td></tr>\n";
  }
  h << "</table>\n";
  if (!c.warnings.empty()) {
    h << "<h3>Warnings</h3><ul>\n";
    for (const std::string& w : c.warnings) h << "<li>" << XmlEscape(w) << "</li>\n";
    h << "</ul>\n";
  }
  h << "</body></html>\n";
  return h.str();
}

}  // namespace groundline::calibration
