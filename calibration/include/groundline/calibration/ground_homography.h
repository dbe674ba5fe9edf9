// A ground homography given directly, as some robots ship it instead of
// camera extrinsics: Duckietown's per-robot calibration files. Two YAML
// layouts are read; both map the image TO the floor, floor units are metres:
//
// 1. Legacy per-robot file (robot_calibrations/camera_extrinsic/<robot>.yaml):
//      homography: [h00, h01, h02, h10, h11, h12, h20, h21, h22]   (row-major)
//    Input: pixel (u, v) of the RECTIFIED image whose pinhole matrix is the
//    left 3x3 of the robot's camera_info projection_matrix P (ROS
//    image_geometry rectification). Output: (x, y) in the Duckiebot frame,
//    x forward, y left, origin on the floor at the axle centre (right-handed,
//    z up, like base_link). Checked on the real files: decomposing
//    H_floor_input * P gives orthonormal rotation columns within 10 % and a
//    camera 0.10 m high, 0.05-0.10 m ahead of the axle; with K instead of P it
//    does not (column ratio about 1.5).
//
// 2. Version-2 file (dt_computer_vision's HomographyToolkit, e.g.
//    extrinsics/dd24/real-world/scenario0/homography.yaml):
//      version: '2'
//      date: '2024-08-18T18:29:27'         (optional)
//      homography: [[...], [...], [...]]   (3x3, or 9 numbers row-major)
//    Its header calls it "resolution-independent": the input is the
//    normalized image point (x/z, y/z) of the undistorted viewing ray, i.e.
//    K^-1 (u, v, 1) of an undistorted pixel, which no image size enters.
//    The output frame is the one the Duckietown tool calibrated in, which the
//    file does not state. For the dd24 file it is the calibration board's frame
//    (checked: its 7x5 inner corners, detected in the raw image and unprojected
//    with the dd24 intrinsics, land on the 17 mm grid within 1 mm): origin at
//    the first inner corner OpenCV reports (far left), x to the right in the
//    image, y towards the camera, metres (left-handed seen from above).
//    Files that also carry 'format: resolution-independent' (newer tool
//    versions) store a matrix that must be combined with the image size; they
//    are rejected rather than guessed at.
//
// Sign. A homography is defined up to scale; groundline fixes the sign so that
// lambda (x, y, 1)^T = H_floor_input (a, b, 1)^T has lambda > 0 exactly for
// inputs whose ray meets the floor in front of the camera (lambda is then
// proportional to 1 / depth), which is what BackProjectPixel
// (camera_extrinsics.h) and FloorPointOfPixel below test. For a right-handed
// z-up floor frame and a camera above the floor this is det(H) < 0 (from
// H^-1 = s M [r1 r2 t]: det = -s^3 det(M) height); the legacy file is
// normalized that way. For version 2 the frame's handedness is unknown, so the
// sign is chosen to make lambda > 0 for the normalized input (0, 1), the ray
// 45 deg below the optical axis towards the image bottom, which meets the floor
// for any upright camera pitched less than 45 deg up; floor_frame_right_handed
// then reports det(H) < 0.
//
// Functions are pure and thread-safe.
#ifndef GROUNDLINE_CALIBRATION_GROUND_HOMOGRAPHY_H_
#define GROUNDLINE_CALIBRATION_GROUND_HOMOGRAPHY_H_

#include <Eigen/Core>
#include <filesystem>
#include <string>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/calibration/camera_model.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

enum class HomographyInput {
  kRectifiedPixel,   // legacy layout: rectified pixel (u, v)
  kNormalizedImage,  // version 2: (x/z, y/z) of the undistorted ray
};

struct GroundHomography {
  Eigen::Matrix3d H_floor_input;  // sign-normalized, see the file comment
  HomographyInput input = HomographyInput::kRectifiedPixel;
  bool floor_frame_right_handed = true;
  std::string date;  // version 2's 'date', else empty
};

// Errors name the file, line and key (missing 'homography', not 9 finite
// numbers, a singular matrix, an unsupported version or format).
core::Result<GroundHomography> ParseGroundHomographyYaml(const std::string& yaml_text,
                                                         const std::string& source_name);
core::Result<GroundHomography> ReadGroundHomographyYaml(const std::filesystem::path& path);

// The homography from normalized image coordinates to the floor:
// H_floor_input for kNormalizedImage, H_floor_input * K_rectified for
// kRectifiedPixel (K_rectified: the rectified image's pinhole matrix, P's left
// 3x3 for the legacy files; ignored for version 2).
Eigen::Matrix3d FloorFromNormalizedImage(const GroundHomography& homography,
                                         const Eigen::Matrix3d& K_rectified);

// The floor point seen at a raw (distorted) pixel: the pixel is unprojected
// through `camera` to (x/z, y/z), then mapped by H_floor_norm (from
// FloorFromNormalizedImage). Fails when the pixel cannot be unprojected or lies
// on or above the horizon (lambda <= 0). J_floor_pixel, if given, is
// d(x, y)/d(u, v) (2x2, floor units per px).
core::Result<Eigen::Vector2d> FloorPointOfPixel(const CameraModel& camera,
                                                const Eigen::Matrix3d& H_floor_norm,
                                                const Eigen::Vector2d& pixel,
                                                Eigen::Matrix2d* J_floor_pixel = nullptr);

// The camera mount a ground homography implies, with the homography's floor
// frame as base_link: FloorFromNormalizedImage(homography, K_rectified)
// inverted and decomposed by MountFromFloorHomography (camera_extrinsics.h).
// A left-handed floor frame (floor_frame_right_handed false: the version-2
// board frame, x to the right in the image, y towards the camera) is mirrored
// in y first (mirrored_y), so that base_link is right-handed: the board's x,
// and y away from the camera. Errors as MountFromFloorHomography's, prefixed
// with "ground homography". A legacy file needs the P of its own camera_info:
// with K instead, the mount comes out distorted (its columns are then about
// 1.5 apart in length, at the limit MountFromFloorHomography accepts).
struct GroundHomographyMount {
  CameraMount mount;
  bool mirrored_y = false;
};
core::Result<GroundHomographyMount> MountFromGroundHomography(const GroundHomography& homography,
                                                              const Eigen::Matrix3d& K_rectified);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_GROUND_HOMOGRAPHY_H_
