// The PASS/FAIL of a floor calibration, its thresholds file and its advice
// (floor_calibration.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <string>

#include "groundline/calibration/floor_calibration.h"
#include "report_config.h"

namespace groundline::calibration {
namespace {

constexpr const char* kQuadrantNames[4] = {"top-left", "top-right", "bottom-left", "bottom-right"};
constexpr const char* kMountNames[6] = {"height", "pitch",          "roll",
                                        "yaw",    "forward offset", "lateral offset"};

std::string Format(const char* format, double a, double b) {
  char text[128];
  std::snprintf(text, sizeof(text), format, a, b);
  return text;
}

// The mount parameter whose own variance moves the 2 m BEV point the most.
int DominantBevParameter(const FloorCalibration& c) {
  int best = 0;
  double best_mm = -1.0;
  for (int i = 0; i < 6; ++i) {
    Matrix6d only = Matrix6d::Zero();
    only(i, i) = c.solution.covariance(i, i);
    const core::Result<BevError> e = BevErrorAhead(c.solution.mount, only, 2.0);
    if (e.ok() && e->rms_mm > best_mm) {
      best_mm = e->rms_mm;
      best = i;
    }
  }
  return best;
}

}  // namespace

core::Status FloorReportThresholds::Validate() const {
  if (!(max_bev_error_2m_mm > 0.0)) return core::Status::Error("max_bev_error_2m_mm must be > 0");
  if (!(max_image_rms_px > 0.0)) return core::Status::Error("max_image_rms_px must be > 0");
  if (!(max_tag_rms_px > 0.0)) return core::Status::Error("max_tag_rms_px must be > 0");
  if (min_corners_per_quadrant < 1) {
    return core::Status::Error("min_corners_per_quadrant must be >= 1");
  }
  return core::Status::Ok();
}

core::Result<FloorReportThresholds> ReadFloorReportThresholds(const std::filesystem::path& path) {
  FloorReportThresholds t;
  if (core::Status s =
          internal::ReadConfigSection(path, "floor_report",
                                      {{"max_bev_error_2m_mm", &t.max_bev_error_2m_mm},
                                       {"max_image_rms_px", &t.max_image_rms_px},
                                       {"max_tag_rms_px", &t.max_tag_rms_px},
                                       {"require_all_quadrants", &t.require_all_quadrants},
                                       {"min_corners_per_quadrant", &t.min_corners_per_quadrant}});
      !s.ok()) {
    return s;
  }
  if (core::Status s = t.Validate(); !s.ok()) {
    return core::Status::Error(path.string() + ": key 'floor_report': " + s.message());
  }
  return t;
}

void JudgeFloorCalibration(const CameraModel& camera, const FloorReportThresholds& thresholds,
                           FloorCalibration* c) {
  c->thresholds = thresholds;
  c->failures.clear();
  c->advice.clear();
  c->quadrant_corners = {};
  const int w = camera.width_px(), h = camera.height_px();
  // Squared residual sums per (image, tag): a bad tag is off in every image
  // that sees it, a bad image (wrong vehicle pose, blur) in most of its tags.
  struct Sum {
    double sq = 0.0;
    int n = 0;
    double Rms() const { return std::sqrt(sq / std::max(1, n)); }
  };
  std::vector<std::map<int, Sum>> per_image(c->images.size());
  for (std::size_t i = 0; i < c->images.size(); ++i) {
    const FloorImage& im = c->images[i];
    for (const FloorCorner& corner : im.corners) {
      const int q =
          (corner.pixel.x() >= 0.5 * (w - 1) ? 1 : 0) + (corner.pixel.y() >= 0.5 * (h - 1) ? 2 : 0);
      ++c->quadrant_corners[q];
      const core::Result<Eigen::Vector2d> px =
          PredictFloorPixel(camera, c->solution.mount, im.T_floor_base, corner.floor_m);
      Sum& sum = per_image[i][corner.tag_id];
      sum.sq += px.ok() ? (*px - corner.pixel).squaredNorm() : 1e6;
      ++sum.n;
    }
  }
  // An image is broken when more than half of its tags are off in it.
  std::vector<bool> broken(c->images.size(), false);
  for (std::size_t i = 0; i < c->images.size(); ++i) {
    int off = 0;
    for (const auto& [id, sum] : per_image[i]) off += sum.Rms() > thresholds.max_tag_rms_px;
    broken[i] = 2 * off > static_cast<int>(per_image[i].size());
  }
  // Tags over the images that are not broken.
  std::map<int, Sum> tag_sum;
  std::map<int, int> tag_images;
  for (std::size_t i = 0; i < c->images.size(); ++i) {
    if (broken[i]) continue;
    for (const auto& [id, sum] : per_image[i]) {
      tag_sum[id].sq += sum.sq;
      tag_sum[id].n += sum.n;
      ++tag_images[id];
    }
  }
  c->tags.clear();
  std::set<int> bad_tags;
  for (const auto& [id, sum] : tag_sum) {
    c->tags.push_back({id, tag_images[id], sum.Rms()});
    if (sum.Rms() > thresholds.max_tag_rms_px) bad_tags.insert(id);
  }
  std::stable_sort(c->tags.begin(), c->tags.end(),
                   [](const TagResidual& a, const TagResidual& b) { return a.rms_px > b.rms_px; });
  // Images over the tags that pass: a bad tag does not fail every image it is in.
  c->image_rms_checked_px.assign(c->images.size(), 0.0);
  c->image_failed.assign(c->images.size(), false);
  std::vector<std::size_t> bad_images;
  for (std::size_t i = 0; i < c->images.size(); ++i) {
    Sum sum;
    for (const auto& [id, s] : per_image[i]) {
      if (bad_tags.count(id)) continue;
      sum.sq += s.sq;
      sum.n += s.n;
    }
    c->image_rms_checked_px[i] = sum.Rms();
    if (broken[i] || sum.Rms() > thresholds.max_image_rms_px) {
      bad_images.push_back(i);
      c->image_failed[i] = true;
    }
  }

  if (!(c->bev[1].rms_mm <= thresholds.max_bev_error_2m_mm)) {
    c->failures.push_back(Format("BEV error at 2 m %.2f mm > %.2f mm", c->bev[1].rms_mm,
                                 thresholds.max_bev_error_2m_mm));
    c->advice.push_back(std::string("the mount is too uncertain, most of all its ") +
                        kMountNames[DominantBevParameter(*c)] +
                        ": add vehicle poses (images) with tags spread over the whole image, "
                        "near its bottom and top edges and both sides, and more tags ahead");
  }
  for (const std::size_t i : bad_images) {
    const double rms = broken[i] ? c->solution.image_rms_px[i] : c->image_rms_checked_px[i];
    c->failures.push_back(c->images[i].name + Format(": corner RMS %.3f px > %.3f px", rms,
                                                     thresholds.max_image_rms_px));
  }
  if (!bad_images.empty() && bad_images.size() == c->images.size() && c->images.size() > 1) {
    c->advice.push_back(
        "every image is off: check the intrinsics (calibrate intrinsics), the tag sizes in the "
        "layout (measure the printed black square) and that the tags lie flat");
  } else {
    for (const std::size_t i : bad_images) {
      c->advice.push_back("drop or retake image " + c->images[i].name +
                          " (if it is sharp, check its surveyed vehicle pose in the layout)");
    }
  }
  for (const TagResidual& t : c->tags) {
    if (!bad_tags.count(t.id)) continue;
    const std::string id = std::to_string(t.id);
    c->failures.push_back(
        "tag " + id +
        Format(": corner RMS %.3f px > %.3f px", t.rms_px, thresholds.max_tag_rms_px));
    c->advice.push_back("re-survey tag " + id + " (its surveyed pose or size disagrees with " +
                        "the other tags, seen in " + std::to_string(t.images) +
                        " images) or remove it from the layout");
  }
  if (thresholds.require_all_quadrants) {
    for (int q = 0; q < 4; ++q) {
      if (c->quadrant_corners[q] >= thresholds.min_corners_per_quadrant) continue;
      c->failures.push_back(std::string(kQuadrantNames[q]) + " image quadrant: " +
                            std::to_string(c->quadrant_corners[q]) + " tag corners < " +
                            std::to_string(thresholds.min_corners_per_quadrant));
      c->advice.push_back(std::string("add tags or vehicle poses so that tags appear in the ") +
                          kQuadrantNames[q] + " of the image");
    }
  }
  c->pass = c->failures.empty();
  c->verdict = "PASS";
  if (!c->pass) {
    c->verdict = "FAIL:";
    for (const std::string& f : c->failures) c->verdict += " " + f + ";";
  }
}

}  // namespace groundline::calibration
