// report.html: one self-contained page, plots as inline SVG.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "groundline/calibration/calibration_report.h"
#include "xml_text.h"

namespace groundline::calibration {
namespace {

std::string Fmt(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

constexpr double kPlotWidth = 640.0;

// Observed corners (grey dots) with their residuals as arrows, magnified so
// that the 95th percentile residual is 20 plot pixels; outliers in red.
std::string ResidualFieldSvg(const IntrinsicCalibration& c) {
  const double scale = kPlotWidth / c.camera.width_px();
  const double height = c.camera.height_px() * scale;
  std::vector<double> norms;
  for (const ViewResult& v : c.views) {
    for (std::size_t j = 0; j < v.residual_px.size(); ++j) {
      if (!v.outlier[j]) norms.push_back(v.residual_px[j].norm());
    }
  }
  double p95 = 1.0;
  if (!norms.empty()) {
    std::sort(norms.begin(), norms.end());
    p95 = std::max(1e-6, norms[static_cast<std::size_t>(0.95 * (norms.size() - 1))]);
  }
  const double gain = 20.0 / p95;
  std::ostringstream s;
  s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << kPlotWidth << "' height='"
    << height + 20 << "'><rect width='" << kPlotWidth << "' height='" << height
    << "' fill='#fff' stroke='#888'/>";
  for (const ViewResult& v : c.views) {
    for (std::size_t j = 0; j < v.residual_px.size(); ++j) {
      const Eigen::Vector2d a = v.observed_px[j] * scale;
      const Eigen::Vector2d b = a + v.residual_px[j] * gain;
      const char* colour = v.outlier[j] ? "#d00" : "#1565c0";
      s << "<circle cx='" << Fmt("%.1f", a.x()) << "' cy='" << Fmt("%.1f", a.y())
        << "' r='1' fill='#999'/><line x1='" << Fmt("%.1f", a.x()) << "' y1='" << Fmt("%.1f", a.y())
        << "' x2='" << Fmt("%.1f", b.x()) << "' y2='" << Fmt("%.1f", b.y()) << "' stroke='"
        << colour << "' stroke-width='1'/>";
    }
  }
  s << "<text x='6' y='" << height + 15 << "' font-size='12'>arrow gain " << Fmt("%.0f", gain)
    << "x (20 px arrow = " << Fmt("%.3f", p95) << " px residual, the 95th percentile)</text></svg>";
  return s.str();
}

std::string HistogramSvg(const IntrinsicCalibration& c, double max_worst_px) {
  constexpr int kBins = 30;
  const double top = std::max(c.summary.worst_px, max_worst_px) * 1.0001;
  std::vector<int> bins(kBins, 0);
  for (const ViewResult& v : c.views) {
    for (std::size_t j = 0; j < v.residual_px.size(); ++j) {
      if (v.outlier[j]) continue;
      const int b = std::min(kBins - 1, static_cast<int>(v.residual_px[j].norm() / top * kBins));
      ++bins[b];
    }
  }
  const int peak = std::max(1, *std::max_element(bins.begin(), bins.end()));
  const double w = kPlotWidth, h = 220, base = 190, bar = (w - 40) / kBins;
  std::ostringstream s;
  s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << w << "' height='" << h
    << "'><rect width='100%' height='100%' fill='#fff' stroke='#888'/>";
  for (int b = 0; b < kBins; ++b) {
    const double bh = 170.0 * bins[b] / peak;
    s << "<rect x='" << Fmt("%.1f", 20 + b * bar) << "' y='" << Fmt("%.1f", base - bh)
      << "' width='" << Fmt("%.1f", bar - 1) << "' height='" << Fmt("%.1f", bh)
      << "' fill='#1565c0'><title>" << bins[b] << " corners</title></rect>";
  }
  const double x_thr = 20 + max_worst_px / top * (w - 40);
  s << "<line x1='" << x_thr << "' y1='15' x2='" << x_thr << "' y2='" << base
    << "' stroke='#d00' stroke-dasharray='4'/><text x='20' y='" << base + 16
    << "' font-size='12'>0 px</text><text x='" << w - 90 << "' y='" << base + 16
    << "' font-size='12'>" << Fmt("%.2f px", top) << "</text><text x='" << x_thr - 4
    << "' y='28' font-size='12' fill='#d00' text-anchor='end'>worst limit</text><text x='" << w / 2
    << "' y='13' font-size='12' text-anchor='middle'>tallest bar: " << peak
    << " corners</text></svg>";
  return s.str();
}

std::string CoverageSvg(const CalibrationReport& r, const IntrinsicCalibration& c) {
  const int nx = CalibrationReport::kCoverageCellsX, ny = CalibrationReport::kCoverageCellsY;
  const double scale = kPlotWidth / c.camera.width_px();
  const double w = kPlotWidth, h = c.camera.height_px() * scale;
  const int peak = std::max(1, *std::max_element(r.coverage.begin(), r.coverage.end()));
  std::ostringstream s;
  s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << w << "' height='" << h << "'>";
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      const int n = r.coverage[y * nx + x];
      const int shade = n == 0 ? 255 : 230 - static_cast<int>(200.0 * n / peak);
      char colour[16];
      std::snprintf(colour, sizeof(colour), "#%02x%02xff", shade, shade);
      s << "<rect x='" << Fmt("%.1f", x * w / nx) << "' y='" << Fmt("%.1f", y * h / ny)
        << "' width='" << Fmt("%.1f", w / nx) << "' height='" << Fmt("%.1f", h / ny) << "' fill='"
        << (n == 0 ? "#fde0e0" : colour) << "' stroke='#ccc'><title>" << n
        << " corners</title></rect>";
    }
  }
  s << "<line x1='" << w / 2 << "' y1='0' x2='" << w / 2 << "' y2='" << h
    << "' stroke='#000' stroke-width='2'/><line x1='0' y1='" << h / 2 << "' x2='" << w << "' y2='"
    << h / 2 << "' stroke='#000' stroke-width='2'/>";
  const double qx[4] = {w / 4, 3 * w / 4, w / 4, 3 * w / 4};
  const double qy[4] = {h / 4, h / 4, 3 * h / 4, 3 * h / 4};
  for (int q = 0; q < 4; ++q) {
    const bool ok = r.quadrant_corners[q] >= r.thresholds.min_corners_per_quadrant;
    s << "<text x='" << qx[q] << "' y='" << qy[q] << "' font-size='20' text-anchor='middle' fill='"
      << (ok ? "#000" : "#d00") << "'>" << r.quadrant_corners[q] << "</text>";
  }
  // The outer ring the border rule counts, with each zone's count.
  const double bx = r.thresholds.border_fraction * w, by = r.thresholds.border_fraction * h;
  s << "<rect x='" << bx << "' y='" << by << "' width='" << w - 2 * bx << "' height='" << h - 2 * by
    << "' fill='none' stroke='#555' stroke-dasharray='6 4'/>";
  const double zx[8] = {bx / 2, w / 2, w - bx / 2, bx / 2, w - bx / 2, bx / 2, w / 2, w - bx / 2};
  const double zy[8] = {by / 2, by / 2, by / 2, h / 2, h / 2, h - by / 2, h - by / 2, h - by / 2};
  for (int z = 0; z < 8; ++z) {
    const bool ok = r.border_corners[z] >= r.thresholds.min_corners_per_border_zone;
    s << "<text x='" << zx[z] << "' y='" << zy[z] + 5
      << "' font-size='14' text-anchor='middle' font-style='italic' font-weight='bold' "
         "stroke='#fff' stroke-width='3' paint-order='stroke' fill='"
      << (ok ? "#000" : "#d00") << "'>" << r.border_corners[z] << "</text>";
  }
  s << "<rect width='100%' height='100%' fill='none' stroke='#888'/></svg>";
  return s.str();
}

// Colour of a projection uncertainty against its limit: light to mid green
// up to the limit, then yellow through red to dark red at 30x the limit and
// beyond, on a log scale (the values span two decades and more).
std::string UncertaintyColour(double value_px, double limit_px) {
  if (!std::isfinite(value_px)) return "#888888";
  const auto mix = [](const int a[3], const int b[3], double t) {
    char text[16];
    std::snprintf(text, sizeof(text), "#%02x%02x%02x", static_cast<int>(a[0] + t * (b[0] - a[0])),
                  static_cast<int>(a[1] + t * (b[1] - a[1])),
                  static_cast<int>(a[2] + t * (b[2] - a[2])));
    return std::string(text);
  };
  static constexpr int kPale[3] = {241, 248, 233}, kGreen[3] = {124, 179, 66};
  static constexpr int kYellow[3] = {255, 235, 59}, kDarkRed[3] = {127, 0, 0};
  const double ratio = value_px / limit_px;
  if (ratio <= 1.0) return mix(kPale, kGreen, ratio);
  return mix(kYellow, kDarkRed, std::min(1.0, std::log10(ratio) / std::log10(30.0)));
}

// The projection-uncertainty map: one cell per map cell, coloured by
// UncertaintyColour, every fourth cell labelled with its value (px); the
// rows above the floor part of the imager are shaded; a legend below.
std::string UncertaintySvg(const CalibrationReport& r, const IntrinsicCalibration& c) {
  const UncertaintyMap& m = r.uncertainty_map;
  const double scale = kPlotWidth / c.camera.width_px();
  const double w = kPlotWidth, h = c.camera.height_px() * scale;
  const double limit = r.thresholds.max_projection_uncertainty_px;
  const double cw = w / m.cells_x, ch = h / m.cells_y;
  std::ostringstream s;
  s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << w << "' height='" << h + 40 << "'>";
  for (int y = 0; y < m.cells_y; ++y) {
    for (int x = 0; x < m.cells_x; ++x) {
      const double v = m.worst_px[y * m.cells_x + x];
      s << "<rect x='" << Fmt("%.1f", x * cw) << "' y='" << Fmt("%.1f", y * ch) << "' width='"
        << Fmt("%.2f", cw + 0.3) << "' height='" << Fmt("%.2f", ch + 0.3) << "' fill='"
        << UncertaintyColour(v, limit) << "'><title>" << Fmt("%.3f px", v) << "</title></rect>";
    }
  }
  for (int y = 1; y < m.cells_y; y += 4) {
    for (int x = 1; x < m.cells_x; x += 4) {
      const double v = m.worst_px[y * m.cells_x + x];
      s << "<text x='" << Fmt("%.1f", (x + 0.5) * cw) << "' y='" << Fmt("%.1f", (y + 0.5) * ch + 4)
        << "' font-size='12' text-anchor='middle' stroke='#fff' stroke-width='3' "
           "paint-order='stroke'>"
        << (std::isfinite(v) ? Fmt(v < 10 ? "%.2f" : "%.0f", v) : std::string("?")) << "</text>";
    }
  }
  if (r.thresholds.floor_top_fraction > 0.0) {
    s << "<rect width='" << w << "' height='" << r.thresholds.floor_top_fraction * h
      << "' fill='#000' fill-opacity='0.35'><title>not floor</title></rect>";
  }
  s << "<rect width='" << w << "' height='" << h << "' fill='none' stroke='#888'/>";
  // The legend, the limit itself named; labels take about 7 px a character.
  const double legend[6] = {0.0, 0.5, 1.0, 3.0, 10.0, 30.0};  // x the limit
  const bool any_not_computable =
      std::any_of(m.worst_px.begin(), m.worst_px.end(), [](double v) { return !std::isfinite(v); });
  double x = 10;
  for (int i = 0; i < (any_not_computable ? 7 : 6); ++i) {
    const std::string label = i == 6   ? std::string("not computable")
                              : i == 2 ? Fmt("%.3g px limit", limit)
                                       : Fmt("%.3g px", legend[i] * limit);
    s << "<rect x='" << x << "' y='" << h + 12 << "' width='22' height='16' fill='"
      << (i == 6 ? UncertaintyColour(std::nan(""), limit)
                 : UncertaintyColour(std::max(1e-9, legend[i]) * limit, limit))
      << "' stroke='#888'/><text x='" << x + 28 << "' y='" << h + 25 << "' font-size='12'"
      << (i == 2 ? " font-weight='bold'" : "") << ">" << label << "</text>";
    x += 28 + 7.0 * static_cast<double>(label.size()) + 14;
  }
  s << "</svg>";
  return s.str();
}

std::string UncertaintySection(const CalibrationReport& r, const IntrinsicCalibration& c) {
  std::ostringstream h;
  h << "<h2>Projection uncertainty</h2>";
  if (r.uncertainty.empty()) {
    h << "<p class='bad'>Not computed: " << internal::XmlEscape(c.covariance_error) << "</p>";
    return h.str();
  }
  const UncertaintyFigure& judged = r.uncertainty.back();
  h << "<p>How far a point's pixel may be off because the calibration itself is uncertain "
       "(mrcal's method: the covariance of the solve propagated to the projection of a point "
       "at the given range, through the intrinsics and the board poses, mean over the views). "
       "1 sigma, worst direction; corner noise sigma "
    << Fmt("%.3f px", r.observed_pixel_sigma_px)
    << " (from the residuals). mm: the same error on a surface facing the camera at that "
       "range.</p><table><tr><th>range</th><th>worst px</th><th>worst mm</th><th>at pixel</th>"
       "<th>cells not computable</th></tr>";
  for (std::size_t i = 0; i + 1 < r.uncertainty.size(); ++i) {
    const UncertaintyFigure& f = r.uncertainty[i];
    h << "<tr><td style='text-align:left'>" << Fmt("%.0f m", f.range_m) << "</td><td"
      << (f.worst_px > r.thresholds.max_projection_uncertainty_px ? " class='bad'" : "") << ">"
      << Fmt("%.3f", f.worst_px) << "</td><td>" << Fmt("%.2f", f.worst_mm) << "</td><td>"
      << Fmt("%.0f", f.where_px.x()) << ", " << Fmt("%.0f", f.where_px.y()) << "</td><td"
      << (f.cells_not_computable > 0 ? " class='bad'" : "") << ">" << f.cells_not_computable
      << "</td></tr>";
  }
  h << "</table><p>Judged at " << Fmt("%.1f m", judged.range_m) << ": worst "
    << Fmt("%.3f px", judged.worst_px) << ", limit "
    << Fmt("%.3f px", r.thresholds.max_projection_uncertainty_px) << ". Map at "
    << Fmt("%.1f m", r.uncertainty_map.range_m)
    << " (px, 1 sigma; green: within the limit, yellow to dark red: above it, up to 30x):</p>"
    << UncertaintySvg(r, c);
  return h.str();
}

// The intrinsics by name (fx, fy, cx, cy in px; the distortion terms
// unitless), with the 1-sigma of each when the covariance was computed.
std::string IntrinsicsTable(const IntrinsicCalibration& c) {
  // mrcal's LENSMODEL_OPENCV4/5/8/12 and PINHOLE are prefixes of this list
  // (camera_model.h); other models' parameters are numbered.
  static constexpr const char* kOpenCvNames[16] = {"fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2",
                                                   "k3", "k4", "k5", "k6", "s1", "s2", "s3", "s4"};
  const std::string& model = c.camera.lens_model();
  const bool named = model.rfind("LENSMODEL_OPENCV", 0) == 0 || model == "LENSMODEL_PINHOLE";
  const std::vector<double>& values = c.camera.intrinsics();
  std::ostringstream h;
  h << "<table><tr><th>parameter</th><th>unit</th><th>value</th>"
    << (c.covariance ? "<th>1&sigma;</th>" : "") << "</tr>";
  for (std::size_t k = 0; k < values.size(); ++k) {
    h << "<tr><td style='text-align:left'>"
      << (named && k < 16 ? std::string(kOpenCvNames[k]) : "p" + std::to_string(k))
      << "</td><td style='text-align:left'>" << (k < 4 ? "px" : "-") << "</td><td>"
      << Fmt("%.6g", values[k]) << "</td>";
    if (c.covariance) {
      const int i = c.covariance->state_index_intrinsics + static_cast<int>(k);
      h << "<td>" << Fmt("%.3g", std::sqrt(std::max(0.0, c.covariance->covariance(i, i))))
        << "</td>";
    }
    h << "</tr>";
  }
  h << "</table>";
  if (c.covariance) {
    h << "<p>The parameters are correlated: judge the projection uncertainty below, not their "
         "1&sigma;.</p>";
  }
  return h.str();
}

}  // namespace

std::string CalibrationReportHtml(const CalibrationReport& r, const IntrinsicCalibration& c) {
  const IntrinsicCalibrationSummary& s = c.summary;
  std::ostringstream h;
  h << "<!DOCTYPE html><html><head><meta charset='utf-8'><title>groundline intrinsics "
       "report</title>"
       "<style>body{font-family:sans-serif;margin:24px;max-width:1000px}"
       "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:3px "
       "8px;text-align:right}"
       "th{background:#eee}th:first-child{text-align:left}.pass{color:#fff;background:#2e7d32;"
       "padding:4px 12px}"
       ".fail{color:#fff;background:#c62828;padding:4px 12px}.bad{color:#c62828;font-weight:bold}"
       "</style></head><body>";
  h << "<h1>Intrinsic calibration <span class='" << (r.pass ? "pass'>PASS" : "fail'>FAIL")
    << "</span></h1>";
  h << "<p>Target <b>" << internal::XmlEscape(r.target_name) << "</b>, lens model <b>"
    << internal::XmlEscape(c.camera.lens_model()) << "</b>, imager " << c.camera.width_px() << " x "
    << c.camera.height_px() << " px, " << c.views.size() << " views, " << s.points << " corners, "
    << s.outliers << " rejected as outliers by mrcal.</p>";
  h << "<table><tr><th>figure</th><th>value</th><th>limit</th></tr>"
    << "<tr><td style='text-align:left'>RMS (per point: sqrt(mean |r|&sup2;))</td><td"
    << (s.rms_px > r.thresholds.max_rms_px ? " class='bad'" : "") << ">" << Fmt("%.4f px", s.rms_px)
    << "</td><td>" << Fmt("%.2f px", r.thresholds.max_rms_px)
    << "</td></tr><tr><td style='text-align:left'>worst residual |r|</td><td"
    << (s.worst_px > r.thresholds.max_worst_px ? " class='bad'" : "") << ">"
    << Fmt("%.4f px", s.worst_px) << "</td><td>" << Fmt("%.2f px", r.thresholds.max_worst_px)
    << "</td></tr><tr><td style='text-align:left'>views</td><td"
    << (static_cast<int>(c.views.size()) < r.thresholds.min_views ? " class='bad'" : "") << ">"
    << c.views.size() << "</td><td>&ge; " << r.thresholds.min_views
    << "</td></tr><tr><td style='text-align:left'>most board tilt about the vertical / "
       "horizontal axis</td><td"
    << (std::min(r.max_tilt_about_vertical_deg, r.max_tilt_about_horizontal_deg) <
                r.thresholds.min_tilt_deg
            ? " class='bad'"
            : "")
    << ">" << Fmt("%.1f", r.max_tilt_about_vertical_deg) << " / "
    << Fmt("%.1f deg", r.max_tilt_about_horizontal_deg) << "</td><td>&ge; "
    << Fmt("%.0f deg", r.thresholds.min_tilt_deg) << "</td></tr>";
  if (!r.uncertainty.empty()) {
    const UncertaintyFigure& f = r.uncertainty.back();
    h << "<tr><td style='text-align:left'>projection uncertainty at " << Fmt("%.1f m", f.range_m)
      << " (worst, floor part)</td><td"
      << (f.worst_px > r.thresholds.max_projection_uncertainty_px ? " class='bad'" : "") << ">"
      << Fmt("%.3f px", f.worst_px) << "</td><td>"
      << Fmt("%.3f px", r.thresholds.max_projection_uncertainty_px) << "</td></tr>";
  }
  h << "</table><p>Camera fingerprint " << r.camera_fingerprint << "</p>";
  if (!r.pass) {
    h << "<h2>What failed and what to do</h2><ul>";
    for (const std::string& f : r.failures)
      h << "<li class='bad'>" << internal::XmlEscape(f) << "</li>";
    for (const std::string& a : r.advice) h << "<li>" << internal::XmlEscape(a) << "</li>";
    h << "</ul>";
  }
  h << "<h2>Intrinsics</h2>" << IntrinsicsTable(c);
  h << "<p>OpenCV calibrateCamera seed (5 terms): RMS " << Fmt("%.4f px", c.opencv_seed.rms_px)
    << ", fx fy cx cy = ";
  for (int i = 0; i < 4; ++i) h << Fmt("%.3f ", c.opencv_seed.intrinsics[i]);
  h << "</p>";
  h << "<h2>Residual vector field</h2>" << ResidualFieldSvg(c);
  h << "<h2>Residual histogram (|r|, inliers)</h2>" << HistogramSvg(c, r.thresholds.max_worst_px);
  h << "<h2>Corner coverage over the imager</h2><p>Inlier corners per cell (the darkest: "
    << *std::max_element(r.coverage.begin(), r.coverage.end())
    << "); the numbers are the quadrant totals (red: fewer than "
    << r.thresholds.min_corners_per_quadrant << "). Pink cells hold no corner"
    << ". In italics: the corners in each zone of the outer ring (dashed; red: fewer than "
    << r.thresholds.min_corners_per_border_zone << ").</p>" << CoverageSvg(r, c)
    << UncertaintySection(r, c);
  h << "<h2>Per-image residuals (worst first)</h2><table><tr><th>image</th><th>corners</th>"
       "<th>inliers</th><th>RMS px</th><th>worst px</th></tr>";
  for (int i : r.views_by_rms) {
    const ViewResult& v = c.views[i];
    h << "<tr><td style='text-align:left'>" << internal::XmlEscape(v.name) << "</td><td>"
      << v.observed_px.size() << "</td><td>" << v.inliers << "</td><td"
      << (v.rms_px > r.thresholds.max_rms_px ? " class='bad'" : "") << ">" << Fmt("%.4f", v.rms_px)
      << "</td><td" << (v.worst_px > r.thresholds.max_worst_px ? " class='bad'" : "") << ">"
      << Fmt("%.4f", v.worst_px) << "</td></tr>";
  }
  h << "</table>";
  if (!r.rejected.empty()) {
    h << "<h2>Images without a usable board</h2><ul>";
    for (const RejectedImage& x : r.rejected) {
      h << "<li>" << internal::XmlEscape(x.name) << ": " << internal::XmlEscape(x.reason)
        << "</li>";
    }
    h << "</ul>";
  }
  h << "</body></html>\n";
  return h.str();
}

}  // namespace groundline::calibration
