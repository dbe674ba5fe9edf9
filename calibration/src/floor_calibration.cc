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

constexpr double kRectifiedMarginM = 0.1;  // floor shown around the tag field

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
  if (core::Status s = thresholds.Validate(); !s.ok()) return s;
  if (core::Status s = bev_grid.Validate(); !s.ok()) return s;
  return rectification.Validate();
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
  std::vector<cv::Mat> used_images;  // kept for the rectified floor
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
    if (options.rectify) used_images.push_back(image);
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
  FloorExtrinsicsOptions solver = options.solver;
  if (solver.survey_sigma_m == 0.0) solver.survey_sigma_m = layout.survey_sigma_m;
  core::Result<FloorExtrinsicsResult> solution = SolveFloorExtrinsics(camera, out.images, solver);
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
  out.bev_map_grid = options.bev_grid;
  if (core::Result<BevUncertaintyMap> map =
          ComputeBevUncertaintyMap(camera, out.solution, nullptr, options.bev_grid);
      map.ok()) {
    out.bev_map = std::move(map).value();
  } else {
    out.warnings.push_back(map.message());
  }
  JudgeFloorCalibration(camera, options.thresholds, &out);
  if (options.rectify) {
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector2d hi = -lo;
    for (const SurveyedTag& t : layout.tags) {
      for (const Eigen::Vector2d& p : t.CornersInFrame()) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
    }
    const Eigen::Vector2d margin = Eigen::Vector2d::Constant(kRectifiedMarginM);
    std::vector<FloorImageView> views;
    for (std::size_t i = 0; i < used_images.size(); ++i) {
      if (out.image_failed[i]) continue;  // its tags would be ghosts beside their outlines
      const cv::Mat& m = used_images[i];
      views.push_back(
          {m.data, m.cols, m.rows, static_cast<int>(m.step[0]), out.images[i].T_floor_base});
    }
    core::Result<FloorRaster> raster = RectifyFloor(camera, out.solution.mount, views, lo - margin,
                                                    hi + margin, options.rectification);
    if (!raster.ok()) return raster.status().WithContext("floor report");
    out.rectified = std::move(raster).value();
  }
  return out;
}

}  // namespace groundline::calibration
