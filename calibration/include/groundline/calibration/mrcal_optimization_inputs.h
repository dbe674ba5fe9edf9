// mrcal's `optimization_inputs` of an intrinsic calibration, the record a
// .cameramodel carries so that mrcal's tools can recompute the solve and its
// uncertainty (mrcal-show-projection-uncertainty, mrcal.projection_uncertainty).
//
// Format (mrcal 2.2 cameramodel.py, _serialize_optimization_inputs): a numpy
// .npz archive (a zip of one .npy file per key; numpy reads stored, i.e.
// uncompressed, members as well as deflated ones) encoded with base85
// (Python's base64.b85encode alphabet, no padding), written into the
// .cameramodel as a Python bytes literal next to 'icam_intrinsics': 0. None
// values are stored as the empty string, as mrcal does. mrcal's C API has no
// writer for this field (only the Python module does), so groundline writes
// the archive itself: .npy version 1.0 headers, zip "stored" members with
// their CRC-32.
//
// Keys, as mrcal-calibrate-cameras fills them for one camera at the
// reference: intrinsics (1, Nparams), extrinsics_rt_fromref (0, 6),
// frames_rt_toref (Nviews, 6), observations_board (Nviews, H, W, 3: x, y,
// weight; weight -1 for corners not seen or rejected as outliers),
// indices_frame_camintrinsics_camextrinsics (Nviews, 3) int32 (view, 0, -1),
// lensmodel, imagersizes (1, 2) int32, calobject_warp (2,) or None, points,
// observations_point, indices_point_camintrinsics_camextrinsics (None),
// the do_optimize_* / do_apply_* flags, calibration_object_spacing (m),
// verbose, imagepaths.
#ifndef GROUNDLINE_CALIBRATION_MRCAL_OPTIMIZATION_INPUTS_H_
#define GROUNDLINE_CALIBRATION_MRCAL_OPTIMIZATION_INPUTS_H_

#include <cstdint>
#include <string>
#include <vector>

#include "groundline/calibration/intrinsic_calibration.h"

namespace groundline::calibration {

// The base85 text of the .npz (without the b'' around it).
std::string MrcalOptimizationInputsBase85(const IntrinsicCalibration& calibration);

// The building blocks, exposed for tests.
std::string Base85Encode(const std::string& bytes);
std::uint32_t Crc32(const std::string& bytes);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_MRCAL_OPTIMIZATION_INPUTS_H_
