#include "groundline/localization/floor_front_end.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include <Eigen/Eigenvalues>
#include <opencv2/imgproc.hpp>

#include "groundline/calibration/mount_remap.h"
#include "groundline/perception/hesse_line.h"

namespace groundline::localization {
namespace {

// The convex hull of the grid's seen cells, in base_link, counter-clockwise.
FloorView SeenFloor(const perception::BevRemap& remap) {
  std::vector<cv::Point> cells;
  cv::findNonZero(remap.valid_mask(), cells);
  std::vector<cv::Point> hull;
  cv::convexHull(cells, hull);
  FloorView view;
  for (const cv::Point& cell : hull) {
    view.polygon_base_m.push_back(remap.grid().FloorPointOfCell(Eigen::Vector2d(cell.x, cell.y)));
  }
  double twice_area = 0.0;
  for (size_t i = 0; i < view.polygon_base_m.size(); ++i) {
    const Eigen::Vector2d& a = view.polygon_base_m[i];
    const Eigen::Vector2d& b = view.polygon_base_m[(i + 1) % view.polygon_base_m.size()];
    twice_area += a.x() * b.y() - a.y() * b.x();
  }
  if (twice_area < 0.0) std::reverse(view.polygon_base_m.begin(), view.polygon_base_m.end());
  return view;
}

}  // namespace

core::Status FloorFrontEndOptions::Validate() const {
  if (core::Status s = remap.Validate(); !s.ok()) return s.WithContext("remap");
  if (core::Status s = extractor.Validate(); !s.ok()) return s.WithContext("extractor");
  if (core::Status s = texture.Validate(); !s.ok()) return s.WithContext("texture");
  if (!(std::isfinite(texture.grid.cell_m) && texture.grid.cell_m > 0.0 &&
        texture.grid.cell_m <= 0.05)) {
    return core::Status::Error("texture.grid.cell_m: expected a cell side in (0, 0.05] m");
  }
  if (core::Status s = bev.Validate(); !s.ok()) return s;
  if (!(min_frame_stddev >= 0.0 && min_frame_stddev < 128.0)) {
    return core::Status::Error("min_frame_stddev: expected 0..128 grey levels");
  }
  if (!(std::isfinite(mount_error_sightings) && mount_error_sightings >= 1.0)) {
    return core::Status::Error("mount_error_sightings: expected a finite count >= 1");
  }
  return core::Status::Ok();
}

core::Result<FloorFrontEnd> FloorFrontEnd::Create(const calibration::CameraModel& camera,
                                                  const calibration::CameraMount& mount,
                                                  const FloorFrontEndOptions& options) {
  if (core::Status s = options.Validate(); !s.ok()) return s.WithContext("floor front end");
  perception::BevRemap::Options remap_options = options.remap;
  core::Result<perception::BevGridOptions> grid =
      perception::ResolveBevGrid(camera, mount, options.bev);
  if (!grid.ok()) return grid.status().WithContext("floor front end");
  remap_options.grid = *grid;
  return Build(camera, mount, remap_options, options);
}

core::Result<FloorFrontEnd> FloorFrontEnd::Build(const calibration::CameraModel& camera,
                                                 const calibration::CameraMount& mount,
                                                 const perception::BevRemap::Options& remap_options,
                                                 const FloorFrontEndOptions& options) {
  FloorFrontEnd front_end;
  auto remap = std::make_shared<perception::BevRemap>(camera, mount, remap_options);
  if (cv::countNonZero(remap->valid_mask()) == 0) {
    return core::Status::Error(
        "floor front end: the camera sees none of the bird's-eye grid's floor (check the "
        "mount's height and pitch, or the grid extent)");
  }
  front_end.extractor_ = std::make_shared<perception::LineExtractor>(*remap, options.extractor);
  front_end.view_ = std::make_shared<const FloorView>(SeenFloor(*remap));
  front_end.texture_ = std::make_shared<TextureTable>();
  front_end.remap_ = std::move(remap);
  front_end.options_ = options;
  front_end.remap_options_ = remap_options;
  front_end.width_px_ = camera.width_px();
  front_end.height_px_ = camera.height_px();
  front_end.min_frame_stddev_ = options.min_frame_stddev;
  return front_end;
}

core::Result<FloorFrontEnd> FloorFrontEnd::WithMount(
    const calibration::CameraMount& mount, const Eigen::Matrix4d& mount_covariance,
    const std::optional<calibration::CameraMount>& observed) const {
  if (core::Status s = mount.Validate(); !s.ok()) return s.WithContext("floor front end: mount");
  if (observed) {
    if (core::Status s = observed->Validate(); !s.ok()) {
      return s.WithContext("floor front end: observed mount");
    }
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(mount_covariance);
  if (!mount_covariance.allFinite() || !mount_covariance.isApprox(mount_covariance.transpose()) ||
      eig.eigenvalues().minCoeff() < -1e-12 * std::max(1.0, eig.eigenvalues().maxCoeff())) {
    return core::Status::Error(
        "floor front end: the mount's covariance is not symmetric positive semi-definite");
  }
  // The same mount (only its uncertainty changed): the table and the
  // extractor are shared, not rebuilt.
  core::Result<FloorFrontEnd> built =
      calibration::SameMount(mount, remap_->mount(), 0.0)
          ? core::Result<FloorFrontEnd>(*this)
          : Build(remap_->camera(), mount, remap_options_, options_);
  if (!built.ok()) return built.status();
  built->mount_covariance_ = mount_covariance;
  built->observed_mount_.reset();
  if (observed && !calibration::SameMount(*observed, mount, 0.0)) built->observed_mount_ = observed;
  return built;
}

void FloorFrontEnd::ExpressUnderObservedMount(FloorObservations* observations) const {
  if (!observed_mount_) return;
  const calibration::CameraMount& from = remap_->mount();
  const calibration::CameraMount& to = *observed_mount_;
  std::vector<LineObservation> lines;
  lines.reserve(observations->lines.size());
  for (LineObservation& line : observations->lines) {
    Eigen::Vector2d a, b;
    if (!calibration::RemapFloorPoint(line.endpoint_a_base_m, from, to, &a) ||
        !calibration::RemapFloorPoint(line.endpoint_b_base_m, from, to, &b)) {
      continue;  // beyond the observed mount's horizon: not a floor line under it
    }
    const core::Result<perception::HesseLine> through = perception::LineFromPoints(a, b);
    if (!through.ok()) continue;
    // Perception's (rho, alpha) covariance carried over: the map between two
    // mounts a fraction of a degree apart scales the floor by well under 1 %.
    line.covariance =
        perception::CovarianceInDescriptionOf(line.line_base, *through, line.covariance);
    line.line_base = *through;
    line.endpoint_a_base_m = a;
    line.endpoint_b_base_m = b;
    lines.push_back(line);
  }
  observations->lines = std::move(lines);
  std::vector<JunctionObservation> junctions;
  junctions.reserve(observations->junctions.size());
  for (JunctionObservation& junction : observations->junctions) {
    Eigen::Vector2d p;
    if (!calibration::RemapFloorPoint(junction.point_base_m, from, to, &p)) continue;
    junction.point_base_m = p;
    junctions.push_back(junction);
  }
  observations->junctions = std::move(junctions);
}

void FloorFrontEnd::AddMountUncertainty(FloorObservations* observations) const {
  if (mount_covariance_.isZero(0.0)) return;
  const calibration::CameraMount& mount = observed_mount();
  const Eigen::Matrix4d common = options_.mount_error_sightings * mount_covariance_;
  for (LineObservation& line : observations->lines) {
    Eigen::Matrix<double, 2, 4> Ja, Jb;
    Eigen::Matrix2d J_line_a, J_line_b;
    if (!calibration::FloorPointMountJacobian(line.endpoint_a_base_m, mount, &Ja) ||
        !calibration::FloorPointMountJacobian(line.endpoint_b_base_m, mount, &Jb)) {
      continue;
    }
    const core::Result<perception::HesseLine> through = perception::LineFromPoints(
        line.endpoint_a_base_m, line.endpoint_b_base_m, &J_line_a, &J_line_b);
    if (!through.ok()) continue;
    const Eigen::Matrix<double, 2, 4> J = J_line_a * Ja + J_line_b * Jb;
    line.mount_covariance = perception::CovarianceInDescriptionOf(
        *through, line.line_base, J * common * J.transpose());
    line.covariance += line.mount_covariance;
  }
  for (JunctionObservation& junction : observations->junctions) {
    Eigen::Matrix<double, 2, 4> J;
    if (!calibration::FloorPointMountJacobian(junction.point_base_m, mount, &J)) continue;
    junction.covariance += J * common * J.transpose();
  }
}

core::Status FloorFrontEnd::TextureBev(const cv::Mat& grey, BevFrame* out) const {
  if (grey.empty() || grey.type() != CV_8UC1 || grey.cols != width_px_ || grey.rows != height_px_) {
    return core::Status::Error("floor texture: expected an 8-bit grey frame of " +
                               std::to_string(width_px_) + "x" + std::to_string(height_px_) +
                               " px (the camera model's imager)");
  }
  std::call_once(texture_->built, [this] {
    perception::BevRemap::Options o = options_.texture;
    o.grid = remap_options_.grid;
    // As fine as the grid's 4096 cells a side allow.
    o.grid.cell_m =
        std::max({options_.texture.grid.cell_m, (o.grid.x_max_m - o.grid.x_min_m) / 4000.0,
                  (o.grid.y_max_m - o.grid.y_min_m) / 4000.0});
    texture_->remap =
        std::make_shared<const perception::BevRemap>(remap_->camera(), remap_->mount(), o);
  });
  const perception::BevRemap& remap = *texture_->remap;
  remap.Apply(grey, &out->image);
  out->seen = remap.valid_mask();
  out->grid = remap.grid();
  out->mount = remap.mount();
  return core::Status::Ok();
}

core::Result<ConvertedObservations> FloorFrontEnd::Observe(const cv::Mat& grey,
                                                           double stamp_s) const {
  cv::Mat bev;
  return Observe(grey, stamp_s, &bev);
}

core::Result<ConvertedObservations> FloorFrontEnd::Observe(
    const cv::Mat& grey, double stamp_s, cv::Mat* bev,
    perception::ExtractionScratch* scratch) const {
  if (grey.empty() || grey.type() != CV_8UC1) {
    return core::Status::Error("camera frame at " + std::to_string(stamp_s) +
                               " s: expected an 8-bit grey image, got an empty or other-typed one");
  }
  if (grey.cols != width_px_ || grey.rows != height_px_) {
    return core::Status::Error("camera frame at " + std::to_string(stamp_s) + " s: expected " +
                               std::to_string(width_px_) + "x" + std::to_string(height_px_) +
                               " px (the camera model's imager), got " + std::to_string(grey.cols) +
                               "x" + std::to_string(grey.rows));
  }
  if (min_frame_stddev_ > 0.0) {
    // Every 16th pixel of every 16th row: a blank frame shows in any sample.
    double sum = 0.0, sum2 = 0.0;
    long n = 0;
    for (int r = 0; r < grey.rows; r += 16) {
      const std::uint8_t* row = grey.ptr<std::uint8_t>(r);
      for (int c = 0; c < grey.cols; c += 16, ++n) {
        sum += row[c];
        sum2 += static_cast<double>(row[c]) * row[c];
      }
    }
    const double mean = sum / static_cast<double>(n);
    const double stddev = std::sqrt(std::max(0.0, sum2 / static_cast<double>(n) - mean * mean));
    if (stddev < min_frame_stddev_) {
      return core::Status::Error("camera frame at " + std::to_string(stamp_s) +
                                 " s: blank (grey level " + std::to_string(static_cast<int>(mean)) +
                                 ", spread " + std::to_string(stddev) + " < " +
                                 std::to_string(min_frame_stddev_) + "): covered or failed camera");
    }
  }
  remap_->Apply(grey, bev);
  perception::ExtractionScratch local;
  ConvertedObservations converted = ObservationsFromExtraction(
      stamp_s, extractor_->Extract(*bev, scratch != nullptr ? scratch : &local));
  ExpressUnderObservedMount(&converted.observations);
  converted.observations.camera_mount = observed_mount();
  converted.observations.view = view_;
  AddMountUncertainty(&converted.observations);
  return converted;
}

}  // namespace groundline::localization
