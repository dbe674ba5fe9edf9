#include "groundline/calibration/floor_calibration.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <set>

namespace groundline::calibration {
namespace {

bool IsImageFile(const std::filesystem::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".png" || ext == ".pgm" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" ||
         ext == ".tif" || ext == ".tiff";
}

// (image name, T_floor_base) of every image to use.
core::Result<std::vector<std::pair<std::string, core::SE2>>> ImageList(
    const TagLayout& layout, const std::filesystem::path& dir) {
  std::vector<std::pair<std::string, core::SE2>> list;
  if (layout.frame == TagLayoutFrame::kFloor) {
    for (const VehiclePose& p : layout.vehicle_poses) list.emplace_back(p.image, p.T_floor_base);
    return list;
  }
  std::error_code ec;
  std::filesystem::directory_iterator it(dir, ec);
  if (ec)
    return core::Status::Error(dir.string() + ": cannot list the image directory: " + ec.message());
  for (const auto& entry : it) {
    if (entry.is_regular_file() && IsImageFile(entry.path())) {
      list.emplace_back(entry.path().filename().string(), core::SE2::Identity());
    }
  }
  std::sort(list.begin(), list.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  if (list.empty()) return core::Status::Error(dir.string() + ": no image files");
  return list;
}

}  // namespace

core::Status FloorCalibrationOptions::Validate() const {
  if (core::Status s = detector.Validate(); !s.ok()) return s;
  if (core::Status s = solver.Validate(); !s.ok()) return s;
  if (!(max_bev_error_2m_mm > 0.0) || !(max_image_rms_px > 0.0)) {
    return core::Status::Error("FloorCalibrationOptions: thresholds must be > 0");
  }
  return core::Status::Ok();
}

core::Result<FloorCalibration> CalibrateFloor(const CameraModel& camera, const TagLayout& layout,
                                              const std::filesystem::path& image_dir,
                                              const FloorCalibrationOptions& options) {
  if (core::Status s = options.Validate(); !s.ok()) return s;
  if (core::Status s = layout.Validate(); !s.ok()) return s;
  core::Result<std::vector<std::pair<std::string, core::SE2>>> list = ImageList(layout, image_dir);
  if (!list.ok()) return list.status();
  FloorCalibration out;
  std::set<int> seen;
  for (const auto& [name, T_floor_base] : *list) {
    const std::filesystem::path path = image_dir / name;
    const cv::Mat image = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
    if (image.empty()) {
      return core::Status::Error(path.string() + ": cannot read the image (listed in the layout)");
    }
    if (image.cols != camera.width_px() || image.rows != camera.height_px()) {
      return core::Status::Error(path.string() + ": image is " + std::to_string(image.cols) + "x" +
                                 std::to_string(image.rows) + " but the camera model is " +
                                 std::to_string(camera.width_px()) + "x" +
                                 std::to_string(camera.height_px()));
    }
    const std::vector<TagDetection> found = DetectTags(
        image.data, image.cols, image.rows, static_cast<int>(image.step[0]), options.detector);
    FloorImage im{name, T_floor_base, {}};
    std::vector<int> unknown;
    for (const TagDetection& d : found) {
      const SurveyedTag* tag = layout.FindTag(d.id);
      if (tag == nullptr) {
        unknown.push_back(d.id);
        continue;
      }
      seen.insert(d.id);
      const auto corners = tag->CornersInFrame();
      for (int k = 0; k < 4; ++k) im.corners.push_back({d.id, k, corners[k], d.corners_px[k]});
    }
    for (const int id : unknown) {
      out.warnings.push_back(name + ": tag " + std::to_string(id) +
                             " is not in the layout; ignored");
    }
    if (im.corners.empty()) {
      out.warnings.push_back(name + ": no tag of the layout found; image skipped");
      continue;
    }
    out.images.push_back(std::move(im));
  }
  for (const SurveyedTag& t : layout.tags) {
    if (!seen.count(t.id)) {
      out.warnings.push_back("tag " + std::to_string(t.id) + " of the layout was never seen");
    }
  }
  if (out.images.empty()) {
    return core::Status::Error(image_dir.string() + ": no image shows a tag of the layout (" +
                               std::to_string(list->size()) + " images searched)");
  }
  core::Result<FloorExtrinsicsResult> solution =
      SolveFloorExtrinsics(camera, out.images, options.solver);
  if (!solution.ok()) return solution.status();
  out.solution = std::move(solution).value();
  const std::array<double, 3> distances = {1.0, 2.0, 4.0};
  for (int i = 0; i < 3; ++i) {
    core::Result<BevError> e =
        BevErrorAhead(out.solution.mount, out.solution.covariance, distances[i]);
    if (e.ok()) {
      out.bev[i] = *e;
    } else {
      out.bev[i].distance_m = distances[i];
      out.bev[i].rms_mm = out.bev[i].sigma3_mm = std::numeric_limits<double>::infinity();
    }
  }
  std::vector<std::string> reasons;
  if (!(out.bev[1].rms_mm <= options.max_bev_error_2m_mm)) {
    char buf[160];
    std::snprintf(buf, sizeof(buf), "BEV error at 2 m %.2f mm > %.2f mm", out.bev[1].rms_mm,
                  options.max_bev_error_2m_mm);
    reasons.push_back(buf);
  }
  for (std::size_t i = 0; i < out.images.size(); ++i) {
    if (out.solution.image_rms_px[i] > options.max_image_rms_px) {
      char buf[200];
      std::snprintf(buf, sizeof(buf), "%s: corner RMS %.3f px > %.3f px",
                    out.images[i].name.c_str(), out.solution.image_rms_px[i],
                    options.max_image_rms_px);
      reasons.push_back(buf);
    }
  }
  out.pass = reasons.empty();
  out.verdict = "PASS";
  if (!out.pass) {
    out.verdict = "FAIL:";
    for (const std::string& r : reasons) out.verdict += " " + r + ";";
  }
  return out;
}

}  // namespace groundline::calibration
