// mrcal's .cameramodel files (http://mrcal.secretsauce.net/cameramodels.html):
// a Python-dict text with the keys
//
//   'lensmodel':  'LENSMODEL_OPENCV8',
//   'intrinsics': [ fx, fy, cx, cy, distortion... ],   (mrcal's order, px)
//   'extrinsics': [ rx, ry, rz, tx, ty, tz ],          (rt_cam_ref, see below)
//   'imagersize': [ width, height ],                   (px)
//
// Reading goes through mrcal's own C parser (mrcal_read_cameramodel_string),
// so what mrcal accepts is what groundline accepts. Writing does NOT use
// mrcal_write_cameramodel_file: mrcal 2.2 prints intrinsics with "%f", six
// decimals, which loses calibration precision. groundline writes every number
// in the shortest text that reads back to the same double, then re-reads the
// text with mrcal's parser and refuses to write unless mrcal recovers every
// value bit for bit.
//
// rt_cam_ref is mrcal's pose of the camera relative to its calibration
// reference: p_cam = R(r) p_ref + t, r a Rodrigues vector (rad), t in the
// calibration's length unit. It is kept for round trips and mrcal's tools;
// groundline's camera mount on the vehicle lives in the extrinsics YAML
// (docs/extrinsics.md), not here.
//
// Functions are reentrant; each call owns everything it allocates.
#ifndef GROUNDLINE_CALIBRATION_MRCAL_CAMERAMODEL_IO_H_
#define GROUNDLINE_CALIBRATION_MRCAL_CAMERAMODEL_IO_H_

#include <array>
#include <filesystem>
#include <string>

#include "groundline/calibration/camera_model.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

struct MrcalCameraModelFile {
  CameraModel camera;
  std::array<double, 6> rt_cam_ref{};  // rx ry rz (rad) tx ty tz
};

// Parses .cameramodel text; source_name names it in messages. Fails when a
// required key is missing, when mrcal's parser rejects the text (its own
// diagnostic goes to stderr), or when the model does not pass
// CameraModel::Create (unknown or CAHVORE model, fx or fy <= 0, ...).
core::Result<MrcalCameraModelFile> ParseMrcalCameraModel(const std::string& text,
                                                         const std::string& source_name);
core::Result<MrcalCameraModelFile> ReadMrcalCameraModel(const std::filesystem::path& path);

// The .cameramodel text of a camera (full precision, see the file comment).
// optimization_inputs_base85, when not empty, is written as mrcal's
// 'optimization_inputs' (with 'icam_intrinsics': 0;
// mrcal_optimization_inputs.h). Fails only if mrcal's parser would not read
// the text back exactly.
core::Result<std::string> MrcalCameraModelToText(
    const CameraModel& camera, const std::array<double, 6>& rt_cam_ref = {},
    const std::string& optimization_inputs_base85 = "");

// Writes atomically (PATH.tmp.<pid>, then renamed over PATH).
core::Status WriteMrcalCameraModel(const std::filesystem::path& path, const CameraModel& camera,
                                   const std::array<double, 6>& rt_cam_ref = {},
                                   const std::string& optimization_inputs_base85 = "");

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_MRCAL_CAMERAMODEL_IO_H_
