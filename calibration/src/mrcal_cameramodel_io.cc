#include "groundline/calibration/mrcal_cameramodel_io.h"

#include <cmath>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "groundline/core/atomic_file.h"
#include "mrcal_adapter.h"
#include "text_util.h"

namespace groundline::calibration {
namespace {

// mrcal's parser needs these four keys; checking them first gives a message
// that names the missing one.
constexpr std::array<const char*, 4> kRequiredKeys = {"lensmodel", "intrinsics", "extrinsics",
                                                      "imagersize"};

bool HasKey(const std::string& text, const std::string& key) {
  return text.find("'" + key + "'") != std::string::npos ||
         text.find("\"" + key + "\"") != std::string::npos;
}

// libmrcal 2.2's lexer scans a quoted string up to its closing quote without
// checking the length it was given, so an unterminated string is read past the
// end of the text (found by fuzzing). The text is checked here first: no NUL
// byte, and every string outside a '#' comment closed on the text, without a
// backslash (mrcal-written names and keys have none, and an escape would let
// mrcal and this scan disagree about where the string ends). Returns what is
// wrong with the line it is on, or "".
std::string LexProblem(const std::string& text) {
  int line = 1, string_line = 0;
  char quote = 0;
  bool comment = false;
  for (const char c : text) {
    if (c == '\0') return "line " + std::to_string(line) + ": a NUL byte (not a text file)";
    if (quote != 0) {
      if (c == '\\') return "line " + std::to_string(line) + ": a backslash in a string";
      if (c == quote) quote = 0;
    } else if (comment) {
      comment = c != '\n';
    } else if (c == '#') {
      comment = true;
    } else if (c == '\'' || c == '"') {
      quote = c;
      string_line = line;
    }
    if (c == '\n') ++line;
  }
  if (quote != 0) {
    return "line " + std::to_string(string_line) + ": a string that is never closed";
  }
  return "";
}

std::string NumberList(const double* values, size_t count) {
  std::string out = "[ ";
  for (size_t i = 0; i < count; ++i) {
    out += text_util::ShortestDecimal(values[i]);
    out += i + 1 < count ? ", " : " ";
  }
  return out + "]";
}

}  // namespace

core::Result<MrcalCameraModelFile> ParseMrcalCameraModel(const std::string& text,
                                                         const std::string& source_name) {
  for (const char* key : kRequiredKeys) {
    if (!HasKey(text, key)) {
      return core::Status::Error(source_name + ": missing key '" + key +
                                 "' (a .cameramodel needs lensmodel, intrinsics, extrinsics and "
                                 "imagersize)");
    }
  }
  if (const std::string problem = LexProblem(text); !problem.empty()) {
    return core::Status::Error(source_name + ": " + problem +
                               "; expected a Python-dict cameramodel as mrcal writes it");
  }
  const mrcal_adapter::CameraModelPtr model = mrcal_adapter::ReadCameraModelString(text);
  if (model == nullptr) {
    return core::Status::Error(source_name +
                               ": mrcal's .cameramodel parser rejected the file (its reason is "
                               "printed on stderr): expected a Python-dict cameramodel as mrcal "
                               "writes it");
  }
  char name[256];
  if (!mrcal_lensmodel_name(name, sizeof(name), &model->lensmodel)) {
    return core::Status::Error(source_name + ": key 'lensmodel': mrcal cannot name the model");
  }
  const int count = mrcal_lensmodel_num_params(&model->lensmodel);
  std::vector<double> intrinsics(model->intrinsics, model->intrinsics + count);
  const unsigned width = model->imagersize[0];
  const unsigned height = model->imagersize[1];
  if (width == 0 || height == 0 || width > 1000000 || height > 1000000) {
    return core::Status::Error(source_name +
                               ": key 'imagersize': expected [width, height] > 0 px, got [" +
                               std::to_string(width) + ", " + std::to_string(height) + "]");
  }
  core::Result<CameraModel> camera = CameraModel::Create(
      name, std::move(intrinsics), static_cast<int>(width), static_cast<int>(height));
  if (!camera.ok()) return camera.status().WithContext(source_name);
  MrcalCameraModelFile file{std::move(camera).value(), {}};
  for (int i = 0; i < 6; ++i) {
    if (!std::isfinite(model->rt_cam_ref[i])) {
      return core::Status::Error(source_name + ": key 'extrinsics': value " + std::to_string(i) +
                                 " is not finite");
    }
    file.rt_cam_ref[static_cast<size_t>(i)] = model->rt_cam_ref[i];
  }
  return file;
}

core::Result<MrcalCameraModelFile> ReadMrcalCameraModel(const std::filesystem::path& path) {
  core::Result<std::string> text = text_util::ReadTextFile(path, ".cameramodel file");
  if (!text.ok()) return text.status();
  return ParseMrcalCameraModel(*text, path.string());
}

core::Result<std::string> MrcalCameraModelToText(const CameraModel& camera,
                                                 const std::array<double, 6>& rt_cam_ref,
                                                 const std::string& optimization_inputs_base85) {
  const std::vector<double>& intrinsics = camera.intrinsics();
  std::ostringstream out;
  out << "# Written by groundline: every number is the shortest text that reads back to the\n"
      << "# same double. Format: http://mrcal.secretsauce.net/cameramodels.html\n"
      << "{\n"
      << "    'lensmodel':  '" << camera.lens_model() << "',\n\n"
      << "    # intrinsics are fx,fy,cx,cy,distortion0,distortion1,....\n"
      << "    'intrinsics': " << NumberList(intrinsics.data(), intrinsics.size()) << ",\n\n"
      << "    # extrinsics are rt_cam_ref: Rodrigues rotation, then translation\n"
      << "    'extrinsics': " << NumberList(rt_cam_ref.data(), rt_cam_ref.size()) << ",\n\n"
      << "    'imagersize': [ " << camera.width_px() << ", " << camera.height_px() << " ],\n";
  if (!optimization_inputs_base85.empty()) {
    out << "\n    'icam_intrinsics': 0,\n\n"
        << "    # The optimization inputs (mrcal's format: a numpy .npz, base85) hold the\n"
        << "    # board observations and the solved state, for mrcal's tools (e.g.\n"
        << "    # mrcal-show-projection-uncertainty). Editing the intrinsics invalidates them.\n"
        << "    'optimization_inputs': b'" << optimization_inputs_base85 << "',\n";
  }
  out << "}\n";
  std::string text = out.str();

  // Refuse to emit anything mrcal would not read back exactly.
  const mrcal_adapter::CameraModelPtr check = mrcal_adapter::ReadCameraModelString(text);
  bool exact = check != nullptr &&
               check->imagersize[0] == static_cast<unsigned>(camera.width_px()) &&
               check->imagersize[1] == static_cast<unsigned>(camera.height_px()) &&
               mrcal_lensmodel_num_params(&check->lensmodel) == static_cast<int>(intrinsics.size());
  for (size_t i = 0; exact && i < intrinsics.size(); ++i)
    exact = check->intrinsics[i] == intrinsics[i];
  for (size_t i = 0; exact && i < 6; ++i) exact = check->rt_cam_ref[i] == rt_cam_ref[i];
  if (!exact) {
    return core::Status::Error(
        "mrcal's parser does not read the generated .cameramodel text "
        "back exactly (lens model " +
        camera.lens_model() + ")");
  }
  return text;
}

core::Status WriteMrcalCameraModel(const std::filesystem::path& path, const CameraModel& camera,
                                   const std::array<double, 6>& rt_cam_ref,
                                   const std::string& optimization_inputs_base85) {
  for (double value : rt_cam_ref) {
    if (!std::isfinite(value)) {
      return core::Status::Error(path.string() + ": refusing to write non-finite extrinsics");
    }
  }
  core::Result<std::string> text =
      MrcalCameraModelToText(camera, rt_cam_ref, optimization_inputs_base85);
  if (!text.ok()) return text.status().WithContext(path.string());
  return core::WriteFileAtomically(path, *text);
}

}  // namespace groundline::calibration
