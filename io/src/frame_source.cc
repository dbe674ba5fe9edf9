#include "groundline/io/frame_source.h"

#include <fnmatch.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "folder_frame_source.h"
#include "groundline/core/text_parse.h"
#include "libcamera_frame_source.h"
#include "v4l2_frame_source.h"

namespace groundline::io {
namespace {

constexpr char kExpected[] =
    "expected folder:DIR, a directory or glob of images, v4l2:/dev/videoN or libcamera:N|ID";

bool IsImageFile(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" || ext == ".pgm" ||
         ext == ".tif" || ext == ".tiff";
}

// Applies one "key=value" of the query to the options of that kind of source.
core::Status ApplyQuery(const std::string& uri, FrameSourceKind kind, std::string_view pair,
                        FrameSourceOptions* options) {
  const std::size_t eq = pair.find('=');
  const std::string key(pair.substr(0, eq));
  const std::string value(eq == std::string_view::npos ? "" : pair.substr(eq + 1));
  const auto error = [&](const std::string& what) {
    return core::Status::Error(uri + ": query '" + std::string(pair) + "': " + what);
  };
  const auto number = [&](double* out) {
    const std::optional<double> v = core::ParseDouble(value);
    if (!v || !(*v > 0.0)) return error("expected a number > 0");
    *out = *v;
    return core::Status::Ok();
  };
  const auto integer = [&](int* out) {
    const std::optional<std::int64_t> v = core::ParseInt(value);
    if (!v || *v <= 0 || *v > 100000) return error("expected an integer > 0");
    *out = static_cast<int>(*v);
    return core::Status::Ok();
  };
  if (kind == FrameSourceKind::kFolder) {
    if (key == "rate") return number(&options->folder_rate_hz);
    return error("unknown key '" + key + "' for a folder (expected rate)");
  }
  if (key == "width") return integer(&options->width_px);
  if (key == "height") return integer(&options->height_px);
  if (key == "fps") return number(&options->fps);
  if (key == "buffers") return integer(&options->buffer_count);
  if (key == "format" && kind == FrameSourceKind::kV4l2) {
    if (value != "GREY" && value != "YUYV" && value != "MJPG") {
      return error("expected format=GREY, YUYV or MJPG");
    }
    options->pixel_format = value;
    return core::Status::Ok();
  }
  return error("unknown key '" + key + "' (expected width, height, fps, buffers" +
               (kind == FrameSourceKind::kV4l2 ? ", format)" : ")"));
}

}  // namespace

core::Status FrameSourceOptions::Validate() const {
  if (!(folder_rate_hz > 0.0)) return core::Status::Error("folder rate must be > 0 Hz");
  if (width_px < 0 || height_px < 0 || (width_px > 0) != (height_px > 0)) {
    return core::Status::Error("camera size: give both width and height (> 0) or neither");
  }
  if (!(fps >= 0.0)) return core::Status::Error("fps must be >= 0 (0: the driver's default)");
  if (!pixel_format.empty() && pixel_format != "GREY" && pixel_format != "YUYV" &&
      pixel_format != "MJPG") {
    return core::Status::Error("pixel format '" + pixel_format + "': expected GREY, YUYV or MJPG");
  }
  if (buffer_count < 2 || buffer_count > 32) {
    return core::Status::Error("buffer count must be in [2, 32]");
  }
  return core::Status::Ok();
}

core::Result<FrameSourceUri> ParseFrameSourceUri(const std::string& uri,
                                                 const FrameSourceOptions& defaults) {
  if (uri.empty()) return core::Status::Error(std::string("empty frame source URI: ") + kExpected);
  FrameSourceUri out;
  out.options = defaults;
  std::string rest = uri;
  const std::size_t colon = uri.find(':');
  const std::string scheme = colon == std::string::npos ? "" : uri.substr(0, colon);
  const bool looks_like_scheme =
      scheme.size() >= 2 && std::all_of(scheme.begin(), scheme.end(), [](unsigned char c) {
        return std::isalnum(c) != 0 || c == '+' || c == '-' || c == '.';
      });
  if (scheme == "folder") {
    out.kind = FrameSourceKind::kFolder;
    rest = uri.substr(colon + 1);
  } else if (scheme == "v4l2") {
    out.kind = FrameSourceKind::kV4l2;
    rest = uri.substr(colon + 1);
  } else if (scheme == "libcamera") {
    out.kind = FrameSourceKind::kLibcamera;
    rest = uri.substr(colon + 1);
  } else if (looks_like_scheme && !std::filesystem::exists(uri)) {
    return core::Status::Error(uri + ": unknown source scheme '" + scheme + ":'; " + kExpected);
  }
  // A folder glob may use '?' as a wildcard: there only a last '?' followed
  // by key=value starts the query.
  std::size_t question = rest.find('?');
  if (out.kind == FrameSourceKind::kFolder) {
    question = rest.rfind('?');
    if (question != std::string::npos && rest.find('=', question) == std::string::npos) {
      question = std::string::npos;
    }
  }
  out.location = rest.substr(0, question);
  if (question != std::string::npos) {
    for (std::string_view pair :
         core::SplitDelimited(std::string_view(rest).substr(question + 1), '&')) {
      if (core::Status s = ApplyQuery(uri, out.kind, pair, &out.options); !s.ok()) return s;
    }
  }
  if (out.location.empty()) {
    return core::Status::Error(uri + ": no " +
                               (out.kind == FrameSourceKind::kFolder ? "directory"
                                : out.kind == FrameSourceKind::kV4l2 ? "device path"
                                                                     : "camera index or id") +
                               " after the scheme; " + kExpected);
  }
  if (out.kind == FrameSourceKind::kV4l2 && out.location.front() != '/') {
    return core::Status::Error(uri + ": expected an absolute device path, e.g. v4l2:/dev/video0");
  }
  if (core::Status s = out.options.Validate(); !s.ok()) return s.WithContext(uri);
  return out;
}

core::Result<std::unique_ptr<FrameSource>> OpenFrameSource(const std::string& uri,
                                                           const FrameSourceOptions& defaults) {
  core::Result<FrameSourceUri> parsed = ParseFrameSourceUri(uri, defaults);
  if (!parsed.ok()) return parsed.status();
  switch (parsed->kind) {
    case FrameSourceKind::kFolder:
      return OpenFolderFrameSource(uri, *parsed);
    case FrameSourceKind::kV4l2:
      return OpenV4l2FrameSource(uri, *parsed);
    case FrameSourceKind::kLibcamera:
      return OpenLibcameraFrameSource(uri, *parsed);
  }
  return core::Status::Error(uri + ": " + kExpected);
}

std::vector<std::string> ListImageFiles(const std::string& spec) {
  namespace fs = std::filesystem;
  std::vector<std::string> files;
  std::error_code ec;
  if (fs::is_directory(spec, ec)) {
    for (const fs::directory_entry& e : fs::directory_iterator(spec, ec)) {
      if (e.is_regular_file() && IsImageFile(e.path())) files.push_back(e.path().string());
    }
  } else {
    const fs::path pattern(spec);
    const fs::path dir = pattern.has_parent_path() ? pattern.parent_path() : fs::path(".");
    for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
      if (e.is_regular_file() && IsImageFile(e.path()) &&
          fnmatch(pattern.filename().c_str(), e.path().filename().c_str(), 0) == 0) {
        files.push_back(e.path().string());
      }
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace groundline::io
