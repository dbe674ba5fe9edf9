// BuildCalibrationReport: the rules of calibration_report.h, the figures
// they are judged on, and the advice for each failure.
#include <Eigen/Geometry>
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "groundline/calibration/calibration_report.h"
#include "imager_zones.h"

namespace groundline::calibration {
namespace {

constexpr const char* kQuadrantNames[4] = {"top-left", "top-right", "bottom-left", "bottom-right"};
using internal::BorderZone;
using internal::kBorderZoneNames;

std::string Fixed(double value, int decimals, const char* unit) {
  char text[48];
  std::snprintf(text, sizeof(text), "%.*f %s", decimals, value, unit);
  return text;
}
std::string Px(double value) { return Fixed(value, 3, "px"); }
// A pixel position rounded as the report's tables print it ("10, 470").
std::string PixelAt(const Eigen::Vector2d& q) {
  char text[48];
  std::snprintf(text, sizeof(text), "%.0f, %.0f", q.x(), q.y());
  return text;
}

std::string Corners(int n) { return std::to_string(n) + (n == 1 ? " corner" : " corners"); }

// Where a pixel is, in the words of the advice.
std::string RegionName(const Eigen::Vector2d& q, int w, int h) {
  static constexpr const char* kNames[9] = {"top-left",    "top",    "top-right",
                                            "left",        "centre", "right",
                                            "bottom-left", "bottom", "bottom-right"};
  const int col = std::clamp(static_cast<int>(3.0 * (q.x() + 0.5) / w), 0, 2);
  const int row = std::clamp(static_cast<int>(3.0 * (q.y() + 0.5) / h), 0, 2);
  return kNames[3 * row + col];
}

void CountCorners(const IntrinsicCalibration& calibration, const ReportThresholds& t,
                  CalibrationReport* report) {
  const int w = calibration.camera.width_px();
  const int h = calibration.camera.height_px();
  constexpr int kCx = CalibrationReport::kCoverageCellsX, kCy = CalibrationReport::kCoverageCellsY;
  report->coverage.assign(kCx * kCy, 0);
  for (const ViewResult& v : calibration.views) {
    for (std::size_t j = 0; j < v.observed_px.size(); ++j) {
      if (v.outlier[j]) continue;
      const Eigen::Vector2d& q = v.observed_px[j];
      ++report
            ->quadrant_corners[(q.x() >= 0.5 * (w - 1) ? 1 : 0) + (q.y() >= 0.5 * (h - 1) ? 2 : 0)];
      const int cx = std::clamp(static_cast<int>((q.x() + 0.5) / w * kCx), 0, kCx - 1);
      const int cy = std::clamp(static_cast<int>((q.y() + 0.5) / h * kCy), 0, kCy - 1);
      ++report->coverage[cy * kCx + cx];
      if (const int zone = BorderZone(q, w, h, t.border_fraction); zone >= 0) {
        ++report->border_corners[zone];
      }
    }
    // Tilt of the board's normal (camera frame) about the camera's y and x axes.
    const Eigen::Vector3d r(v.rt_cam_board[0], v.rt_cam_board[1], v.rt_cam_board[2]);
    const Eigen::Vector3d n = (r.norm() > 0 ? Eigen::AngleAxisd(r.norm(), r.normalized()).matrix()
                                            : Eigen::Matrix3d::Identity())
                                  .col(2);
    constexpr double kDeg = 180.0 / 3.14159265358979323846;
    report->max_tilt_about_vertical_deg = std::max(
        report->max_tilt_about_vertical_deg, std::atan2(std::abs(n.x()), std::abs(n.z())) * kDeg);
    report->max_tilt_about_horizontal_deg = std::max(
        report->max_tilt_about_horizontal_deg, std::atan2(std::abs(n.y()), std::abs(n.z())) * kDeg);
  }
}

// Worst figure of a map over the rows that see the floor.
UncertaintyFigure WorstOnFloor(const UncertaintyMap& map, int w, int h, double floor_top_fraction) {
  UncertaintyFigure worst;
  worst.range_m = map.range_m;
  worst.worst_px = 0.0;
  for (int iy = 0; iy < map.cells_y; ++iy) {
    for (int ix = 0; ix < map.cells_x; ++ix) {
      const Eigen::Vector2d c = map.CellCentre(ix, iy, w, h);
      if (c.y() < floor_top_fraction * h) continue;
      const double px = map.worst_px[iy * map.cells_x + ix];
      if (!std::isfinite(px)) {
        if (worst.cells_not_computable++ == 0) worst.first_not_computable_px = c;
        continue;
      }
      if (px > worst.worst_px) {
        worst.worst_px = px;
        worst.worst_mm = map.worst_mm[iy * map.cells_x + ix];
        worst.where_px = c;
      }
    }
  }
  return worst;
}

}  // namespace

std::string CameraFingerprint(const CameraModel& camera) {
  std::uint64_t hash = 0xcbf29ce484222325ull;
  const auto mix = [&hash](const void* data, std::size_t size) {
    const unsigned char* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) hash = (hash ^ bytes[i]) * 0x100000001b3ull;
  };
  mix(camera.lens_model().data(), camera.lens_model().size());
  const std::int32_t size[2] = {camera.width_px(), camera.height_px()};
  mix(size, sizeof(size));
  for (double q : camera.intrinsics()) {
    const std::uint64_t bits = std::bit_cast<std::uint64_t>(q);
    mix(&bits, sizeof(bits));
  }
  char text[17];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

CalibrationReport BuildCalibrationReport(const IntrinsicCalibration& calibration,
                                         const std::string& target_name,
                                         std::vector<RejectedImage> rejected,
                                         const ReportThresholds& t,
                                         std::vector<std::string> live_missing) {
  CalibrationReport report;
  report.target_name = target_name;
  report.thresholds = t;
  report.rejected = std::move(rejected);
  report.live_missing = std::move(live_missing);
  report.camera_fingerprint = CameraFingerprint(calibration.camera);
  const int w = calibration.camera.width_px();
  const int h = calibration.camera.height_px();
  CountCorners(calibration, t, &report);
  report.views_by_rms.resize(calibration.views.size());
  std::iota(report.views_by_rms.begin(), report.views_by_rms.end(), 0);
  std::stable_sort(report.views_by_rms.begin(), report.views_by_rms.end(), [&](int a, int b) {
    return calibration.views[a].rms_px > calibration.views[b].rms_px;
  });
  const auto fail = [&report](std::string failure, std::string advice) {
    report.failures.push_back(std::move(failure));
    report.advice.push_back(std::move(advice));
  };

  const int n_views = static_cast<int>(calibration.views.size());
  if (n_views < t.min_views) {
    fail(std::to_string(n_views) + " views < " + std::to_string(t.min_views),
         "capture " + std::to_string(t.min_views - n_views) +
             " more view(s): the board near every corner and edge of the image, tilted 30-45 "
             "deg in different directions");
  }
  const IntrinsicCalibrationSummary& s = calibration.summary;
  if (s.rms_px > t.max_rms_px) {
    const ViewResult& worst = calibration.views[report.views_by_rms.front()];
    fail("RMS " + Px(s.rms_px) + " > " + Px(t.max_rms_px),
         worst.rms_px > 2.0 * s.rms_px
             ? "drop or retake image " + worst.name + " (its RMS is " + Px(worst.rms_px) +
                   ", the others' much lower)"
             : "the error is spread over all images: check focus and motion blur, that the "
               "target definition matches the print (measure the scale bar), that the board is "
               "flat, or try a richer lens model (--model LENSMODEL_OPENCV8)");
  }
  if (s.worst_px > t.max_worst_px) {
    const ViewResult* worst_view = &calibration.views.front();
    for (const ViewResult& v : calibration.views)
      if (v.worst_px > worst_view->worst_px) worst_view = &v;
    fail("worst residual " + Px(s.worst_px) + " > " + Px(t.max_worst_px),
         "drop or retake image " + worst_view->name + " (it holds the worst corner, " +
             Px(worst_view->worst_px) + "; look for blur, glare or a misdetected corner)");
  }
  if (t.require_all_quadrants) {
    for (int q = 0; q < 4; ++q) {
      if (report.quadrant_corners[q] >= t.min_corners_per_quadrant) continue;
      fail(std::string(kQuadrantNames[q]) + " quadrant: " + Corners(report.quadrant_corners[q]) +
               " < " + std::to_string(t.min_corners_per_quadrant),
           std::string("take more views with the board in the ") + kQuadrantNames[q] +
               " of the image, close to its corner and edges");
    }
  }
  if (t.require_border_coverage) {
    const int depth_pct = static_cast<int>(std::lround(100.0 * t.border_fraction));
    for (int z = 0; z < 8; ++z) {
      if (report.border_corners[z] >= t.min_corners_per_border_zone) continue;
      fail(std::string("image ") + kBorderZoneNames[z] + " (outer " + std::to_string(depth_pct) +
               "%): " + Corners(report.border_corners[z]) + " < " +
               std::to_string(t.min_corners_per_border_zone),
           std::string("capture views with the board pushed into the image's ") +
               kBorderZoneNames[z] + ", its corners within " + std::to_string(depth_pct) +
               "% of the image border");
    }
  }
  if (report.max_tilt_about_vertical_deg < t.min_tilt_deg) {
    fail("most board tilt about the vertical axis " +
             Fixed(report.max_tilt_about_vertical_deg, 1, "deg") + " < " +
             Fixed(t.min_tilt_deg, 1, "deg"),
         "capture views with the board turned like a door: its left or right edge 30-45 deg "
         "away from the camera");
  }
  if (report.max_tilt_about_horizontal_deg < t.min_tilt_deg) {
    fail("most board tilt about the horizontal axis " +
             Fixed(report.max_tilt_about_horizontal_deg, 1, "deg") + " < " +
             Fixed(t.min_tilt_deg, 1, "deg"),
         "capture views with the board tipped: its top or bottom edge 30-45 deg away from the "
         "camera");
  }
  if (calibration.covariance) {
    report.observed_pixel_sigma_px = calibration.covariance->observed_pixel_sigma_px;
    constexpr int kMapX = 32, kMapY = 24;
    for (double range_m : {1.0, 2.0, 4.0, t.uncertainty_range_m}) {
      UncertaintyMap map = ComputeUncertaintyMap(calibration, range_m, kMapX, kMapY);
      report.uncertainty.push_back(WorstOnFloor(map, w, h, t.floor_top_fraction));
      report.uncertainty_maps.push_back(map);
      report.uncertainty_map = std::move(map);  // the last: uncertainty_range_m
    }
    const UncertaintyFigure& judged = report.uncertainty.back();
    if (judged.cells_not_computable > 0) {
      const Eigen::Vector2d& q = judged.first_not_computable_px;
      fail("projection uncertainty at " + Fixed(judged.range_m, 1, "m") +
               " cannot be computed in " + std::to_string(judged.cells_not_computable) + " of " +
               std::to_string(report.uncertainty_map.cells_x * report.uncertainty_map.cells_y) +
               " map cells, first at pixel " + PixelAt(q) +
               " (the solved lens model does not map those pixels back to rays)",
           "capture views with the board in the image's " + RegionName(q, w, h) +
               ": no corner constrained the lens there");
    }
    if (judged.worst_px > t.max_projection_uncertainty_px) {
      fail("projection uncertainty at " + Fixed(judged.range_m, 1, "m") + " " +
               Px(judged.worst_px) + " (1 sigma, worst direction, at pixel " +
               PixelAt(judged.where_px) + ") > " + Px(t.max_projection_uncertainty_px),
           "capture more views with the board in the image's " + RegionName(judged.where_px, w, h) +
               " (where the camera is least certain), some of them nearer the working "
               "distance");
    }
  } else {
    fail("projection uncertainty unknown (" + calibration.covariance_error + ")",
         "capture more views covering the whole image with varied tilts");
  }
  for (const std::string& m : report.live_missing) {
    fail("live guidance: coverage incomplete: " + m, m);
  }
  report.pass = report.failures.empty();
  return report;
}

}  // namespace groundline::calibration
