// The one place groundline touches libmrcal's C API (mrcal 2.2, Debian
// libmrcal-dev): the header include, RAII ownership of the objects mrcal
// allocates, and views of Eigen storage as mrcal point arrays. Private to the
// calibration module; no public header includes mrcal.
#ifndef GROUNDLINE_CALIBRATION_SRC_MRCAL_ADAPTER_H_
#define GROUNDLINE_CALIBRATION_SRC_MRCAL_ADAPTER_H_

// mrcal.h is a C header without extern "C" guards.
extern "C" {
#include <mrcal/mrcal.h>
}

#include <filesystem>
#include <memory>
#include <string>

namespace groundline::calibration::mrcal_adapter {

// mrcal_read_cameramodel_*() returns a malloc'ed model that only
// mrcal_free_cameramodel() may release.
struct CameraModelDeleter {
  void operator()(mrcal_cameramodel_t* model) const noexcept { mrcal_free_cameramodel(&model); }
};
using CameraModelPtr = std::unique_ptr<mrcal_cameramodel_t, CameraModelDeleter>;

// Null when mrcal cannot open or parse the file (mrcal prints its reason to
// stderr).
inline CameraModelPtr ReadCameraModelFile(const std::filesystem::path& path) {
  return CameraModelPtr(mrcal_read_cameramodel_file(path.c_str()));
}
// libmrcal 2.2's parser skips a '#' comment up to its '\n' without checking
// the length it was given: a text that ends inside a comment is read past its
// end (found by fuzzing). The text it is handed therefore always ends with '\n'.
inline CameraModelPtr ReadCameraModelString(const std::string& text) {
  const std::string terminated = text.empty() || text.back() != '\n' ? text + '\n' : text;
  return CameraModelPtr(
      mrcal_read_cameramodel_string(terminated.data(), static_cast<int>(terminated.size())));
}

// Known defect of libmrcal 2.2's C mrcal_project(): with N > 1 points and a
// dq_dp output it writes every point's 2x3 gradient into the first slot
// (the pixels are right). Callers that need gradients call it with N = 1.
//
// Eigen's column-major 3xN and 2xN storage is exactly mrcal's array of
// mrcal_point3_t / mrcal_point2_t (unions over double[3] / double[2]).
static_assert(sizeof(mrcal_point3_t) == 3 * sizeof(double));
static_assert(sizeof(mrcal_point2_t) == 2 * sizeof(double));
inline const mrcal_point3_t* AsPoint3(const double* xyz) {
  return reinterpret_cast<const mrcal_point3_t*>(xyz);
}
inline mrcal_point3_t* AsPoint3(double* xyz) { return reinterpret_cast<mrcal_point3_t*>(xyz); }
inline const mrcal_point2_t* AsPoint2(const double* xy) {
  return reinterpret_cast<const mrcal_point2_t*>(xy);
}
inline mrcal_point2_t* AsPoint2(double* xy) { return reinterpret_cast<mrcal_point2_t*>(xy); }

}  // namespace groundline::calibration::mrcal_adapter

#endif  // GROUNDLINE_CALIBRATION_SRC_MRCAL_ADAPTER_H_
