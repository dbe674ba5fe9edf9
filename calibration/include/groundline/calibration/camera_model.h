// CameraModel: the intrinsics of one camera (lens model, parameters, imager
// size), projecting through libmrcal 2.2 (mrcal_project / mrcal_unproject).
//
// Frames and units. Points are in the camera optical frame (docs/conventions.md:
// z forward along the optical axis, x right, y down), any length unit. Pixels
// are (u, v) = (column, row) with integer values at pixel centres: the
// top-left pixel covers [-0.5, 0.5] x [-0.5, 0.5] (the mrcal and OpenCV
// convention).
//
// Lens models are mrcal's, named as mrcal names them
// (http://mrcal.secretsauce.net/lensmodels.html); the parameter vector is the
// intrinsics core fx, fy, cx, cy (pixels) followed by the distortion terms in
// mrcal's order, e.g.
//   LENSMODEL_PINHOLE   fx fy cx cy
//   LENSMODEL_OPENCV4   fx fy cx cy k1 k2 p1 p2
//   LENSMODEL_OPENCV5   fx fy cx cy k1 k2 p1 p2 k3
//   LENSMODEL_OPENCV8   fx fy cx cy k1 k2 p1 p2 k3 k4 k5 k6
//   LENSMODEL_OPENCV12  fx fy cx cy k1 k2 p1 p2 k3 k4 k5 k6 s1 s2 s3 s4
//   LENSMODEL_SPLINED_STEREOGRAPHIC_order=3_Nx=16_Ny=12_fov_x_deg=100
//                       fx fy cx cy then 2 Nx Ny spline control values
// The OPENCV models are OpenCV's own equations (cv::projectPoints with the
// same distCoeffs gives the same pixels; the tests check it to 1e-6 px). Every
// model mrcal_project and mrcal_unproject support is accepted except
// LENSMODEL_CAHVORE (no unprojection in mrcal 2.2).
//
// Jacobians are optional output arguments (nullptr to skip):
//   J_pixel_point = d(u, v)/d(x, y, z), 2x3, px per length unit (mrcal's dq_dp);
//   J_ray_pixel   = d(ray)/d(u, v), 3x2. mrcal gives no unprojection gradient,
//   so it is derived from the projection Jacobian J at the ray r: projection is
//   scale invariant (J r = 0), so on the z = 1 plane d(x, y)/d(u, v) is the
//   inverse of J's left 2x2 block; for unit rays J_ray_pixel = T (J T)^-1 with
//   T (3x2) an orthonormal basis of the plane orthogonal to r.
//
// Unprojection is mrcal_unproject (iterative) polished by Newton steps in the
// tangent plane of the ray until the ray reprojects onto the pixel within
// 1e-11 px; a pixel whose ray cannot be brought within 1e-6 px fails.
//
// A CameraModel is an immutable value: cheap to copy (shared immutable state),
// and every method is const and safe to call from several threads at once
// (mrcal 2.2's project/unproject work on call-local state only; its one static,
// a warn-once flag for unprojections it cannot solve precisely, is benign).
#ifndef GROUNDLINE_CALIBRATION_CAMERA_MODEL_H_
#define GROUNDLINE_CALIBRATION_CAMERA_MODEL_H_

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "groundline/core/status.h"

namespace groundline::calibration {

// The lens-model families groundline's readers and writers care about.
enum class LensFamily {
  kPinhole,
  kOpenCv4,
  kOpenCv5,
  kOpenCv8,
  kOpenCv12,
  kSplinedStereographic,
  kOther,  // another mrcal model (stereographic, lonlat, latlon, CAHVOR)
};

enum class RayNormalization {
  kUnitNorm,   // |ray| = 1; works for rays at any angle, also behind the camera
  kZEqualsOne  // ray = (x, y, 1); fails for rays with z <= 0
};

class CameraModel {
 public:
  // Validates and builds a model. lens_model is a full mrcal name (configured,
  // e.g. "..._order=3_Nx=16_Ny=12_fov_x_deg=100" for splined models). Fails,
  // naming the problem, when the name is unknown or unconfigured, the model is
  // not supported (CAHVORE), intrinsics.size() differs from the model's
  // parameter count, a parameter is not finite, fx or fy is <= 0, or the imager
  // size is not positive.
  static core::Result<CameraModel> Create(std::string_view lens_model,
                                          std::vector<double> intrinsics, int width_px,
                                          int height_px);

  // An ideal pinhole camera; the arguments must be valid (asserted).
  static CameraModel Pinhole(double fx, double fy, double cx, double cy, int width_px,
                             int height_px);

  const std::string& lens_model() const;  // the configured mrcal name
  LensFamily family() const;
  const std::vector<double>& intrinsics() const;  // core then distortion, mrcal order
  int width_px() const;
  int height_px() const;
  // The intrinsics core as K = [fx 0 cx; 0 fy cy; 0 0 1] (pixels).
  Eigen::Matrix3d K() const;

  // Pixel of the point p_cam. Fails when p_cam is not finite, is not in front
  // of the camera (z <= 0; the stereographic-type models that can project
  // behind the camera accept any p_cam != 0), or its pixel is not finite.
  // The pixel may lie outside the image: see InImage / IsVisible.
  core::Result<Eigen::Vector2d> Project(const Eigen::Vector3d& p_cam,
                                        Eigen::Matrix<double, 2, 3>* J_pixel_point = nullptr) const;

  // The viewing ray of a pixel. Fails when the pixel is not finite, when the
  // unprojection does not converge (see the file comment), or for kZEqualsOne
  // when the ray does not point forward (z <= 0).
  core::Result<Eigen::Vector3d> Unproject(
      const Eigen::Vector2d& pixel, RayNormalization normalization = RayNormalization::kUnitNorm,
      Eigen::Matrix<double, 3, 2>* J_ray_pixel = nullptr) const;

  // Batched Project over the columns of points_cam (3xN). Resizes *pixels to
  // 2xN and *valid to N; valid[i] = 1 when Project(points_cam.col(i)) would
  // succeed (otherwise pixels.col(i) is unspecified). J_pixel_point, if given,
  // is resized to 6xN: column i is the 2x3 Jacobian of point i, row-major
  // (du/dx du/dy du/dz dv/dx dv/dy dv/dz); with it the points go through mrcal
  // one at a time (libmrcal 2.2's batched gradients are wrong beyond the first
  // point). Returns the number of valid points.
  int ProjectBatch(const Eigen::Ref<const Eigen::Matrix3Xd>& points_cam, Eigen::Matrix2Xd* pixels,
                   std::vector<std::uint8_t>* valid,
                   Eigen::Matrix<double, 6, Eigen::Dynamic>* J_pixel_point = nullptr) const;

  // Batched Unproject over the columns of pixels (2xN), without Jacobians.
  // Resizes *rays to 3xN and *valid to N. Returns the number of valid rays.
  int UnprojectBatch(const Eigen::Ref<const Eigen::Matrix2Xd>& pixels,
                     RayNormalization normalization, Eigen::Matrix3Xd* rays,
                     std::vector<std::uint8_t>* valid) const;

  // True when the pixel lies on the imager: -0.5 <= u <= width - 0.5 and
  // -0.5 <= v <= height - 0.5.
  bool InImage(const Eigen::Vector2d& pixel) const;
  // The valid region: p_cam is in front of the camera (z > 0) and projects
  // into the image. Note: far outside the calibrated field of view a
  // polynomial (OPENCV) model can fold back and map a point into the image
  // anyway; the field of view a calibration covers is the caller's business.
  bool IsVisible(const Eigen::Vector3d& p_cam) const;

  struct Impl;  // opaque; defined in camera_model.cc

 private:
  explicit CameraModel(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}
  std::shared_ptr<const Impl> impl_;  // never null
};

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_CAMERA_MODEL_H_
