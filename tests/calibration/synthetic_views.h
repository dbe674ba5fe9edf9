// Synthetic calibration views for the intrinsics tests: a known OPENCV8
// camera looking at an AprilGrid from seeded random poses, corners projected
// through the camera with Gaussian pixel noise. Tags with a corner off the
// imager are left out (partial views, as in real AprilGrid calibrations).
#ifndef GROUNDLINE_TESTS_CALIBRATION_SYNTHETIC_VIEWS_H_
#define GROUNDLINE_TESTS_CALIBRATION_SYNTHETIC_VIEWS_H_

#include <Eigen/Geometry>
#include <random>
#include <string>
#include <vector>

#include "groundline/calibration/calib_target.h"
#include "groundline/calibration/camera_model.h"
#include "groundline/calibration/intrinsic_calibration.h"
#include "groundline/core/random_draws.h"

namespace groundline::calibration::testing {

inline CameraModel TrueOpencv8Camera() {
  return *CameraModel::Create(
      "LENSMODEL_OPENCV8",
      {500.0, 502.0, 321.0, 239.0, -0.28, 0.09, 0.001, -0.0005, -0.012, 0.01, -0.005, 0.002}, 640,
      480);
}

// Spacing ratio 0.25: the solver's grid pitch is a quarter tag (30 x 20
// points, 96 of them tag corners), which keeps the tests fast.
inline CalibTarget SyntheticAprilGrid() {
  CalibTarget t;
  t.name = "synthetic_aprilgrid_6x4_50mm";
  t.type = TargetType::kAprilGrid;
  t.tags_x = 6;
  t.tags_y = 4;
  t.tag_size_m = 0.05;
  t.spacing_ratio = 0.25;
  t.count = 24;
  return t;
}

// `n` views; top_left_only keeps the whole board in the image's top-left
// quadrant (for coverage-failure tests); reach_borders centres the first 8
// kept views on the image's corners and edge middles, so that the corners
// reach every zone of the imager's outer ring (what the report asks for).
inline std::vector<CalibrationView> SyntheticViews(const CameraModel& camera,
                                                   const CalibTarget& target, const BoardGrid& grid,
                                                   int n, double noise_px, unsigned seed,
                                                   bool top_left_only = false,
                                                   bool reach_borders = false) {
  // Positions for a 640 x 480 imager, scaled to the camera's.
  const double sx = camera.width_px() / 640.0, sy = camera.height_px() / 480.0;
  const double border_u[8] = {40, 320, 600, 40, 600, 40, 320, 600};
  const double border_v[8] = {30, 30, 30, 240, 240, 450, 450, 450};
  int border_slot = reach_borders ? 0 : 8, slot_tries = 0;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, noise_px);
  const Eigen::Vector2d size = target.PatternSize_m();
  std::vector<CalibrationView> views;
  for (int v = 0; views.size() < static_cast<std::size_t>(n) && v < 50 * n; ++v) {
    double z = 0.45 + 0.15 * u(rng);
    const Eigen::Vector2d d = core::DrawVector<2>(u, rng);
    Eigen::Vector2d centre_px(sx * (320 + 200 * d(0)), sy * (240 + 150 * d(1)));
    if (top_left_only) {  // a small board image (~190 px wide) kept in the top-left
      z = 1.0 + 0.05 * u(rng);
      centre_px = {sx * (130 + 40 * u(rng)), sy * (95 + 30 * u(rng))};
    } else if (border_slot < 8) {  // farther: a smaller board image fits the corner
      z = 0.7 + 0.1 * u(rng);
      centre_px = {sx * border_u[border_slot], sy * border_v[border_slot]};
      if (++slot_tries > 30) ++border_slot, slot_tries = 0;  // give this slot up
    }
    const Eigen::Vector3d centre = *camera.Unproject(centre_px, RayNormalization::kZEqualsOne) * z;
    const Eigen::Vector3d angles =
        Eigen::Vector3d(0.5, 0.5, 0.3).cwiseProduct(core::DrawVector<3>(u, rng));
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(angles(0), Eigen::Vector3d::UnitX()) *
                               Eigen::AngleAxisd(angles(1), Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(angles(2), Eigen::Vector3d::UnitZ()))
                                  .toRotationMatrix();
    const Eigen::Vector3d t = centre - R * Eigen::Vector3d(size.x() / 2, size.y() / 2, 0.0);
    CalibrationView view;
    view.name = "synthetic" + std::to_string(views.size()) + ".png";
    for (int id = 0; id < target.count; ++id) {
      std::vector<Eigen::Vector2d> q(4);
      bool inside = true;
      for (int k = 0; k < 4; ++k) {
        const core::Result<Eigen::Vector2d> px =
            camera.Project(R * grid.Point_board(AprilGridCornerIndex(target, grid, id, k)) + t);
        inside = inside && px.ok() && camera.InImage(*px);
        if (px.ok()) q[k] = *px;
      }
      if (!inside) continue;
      for (int k = 0; k < 4; ++k) {
        view.observation.grid_index.push_back(AprilGridCornerIndex(target, grid, id, k));
        view.observation.corners_px.push_back(q[k] + core::DrawVector<2>(noise, rng));
      }
    }
    if (view.observation.grid_index.size() >= 4 * 8) {
      views.push_back(std::move(view));
      if (border_slot < 8 && slot_tries > 0) ++border_slot, slot_tries = 0;
    }
  }
  return views;
}

}  // namespace groundline::calibration::testing

#endif  // GROUNDLINE_TESTS_CALIBRATION_SYNTHETIC_VIEWS_H_
