#include "groundline/calibration/mrcal_optimization_inputs.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <vector>

namespace groundline::calibration {
namespace {

// One .npy file (format version 1.0): magic, header length (little-endian
// uint16), the header dict padded with spaces to a multiple of 64 bytes
// (numpy's alignment) and ended by '\n', then the raw little-endian data.
std::string Npy(const std::string& descr, const std::vector<int>& shape, const std::string& data) {
  std::string shape_text = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    shape_text += std::to_string(shape[i]);
    shape_text += shape.size() == 1 || i + 1 < shape.size() ? "," : "";
    if (i + 1 < shape.size()) shape_text += " ";
  }
  shape_text += ")";
  std::string header =
      "{'descr': '" + descr + "', 'fortran_order': False, 'shape': " + shape_text + ", }";
  const std::size_t total = 10 + header.size() + 1;
  header.append((64 - total % 64) % 64, ' ');
  header += '\n';
  std::string out("\x93NUMPY\x01\x00", 8);
  out += static_cast<char>(header.size() & 0xff);
  out += static_cast<char>(header.size() >> 8);
  return out + header + data;
}

template <typename T>
std::string Bytes(const std::vector<T>& values) {
  static_assert(std::endian::native == std::endian::little);
  std::string out(values.size() * sizeof(T), '\0');
  if (!values.empty()) std::memcpy(out.data(), values.data(), out.size());
  return out;
}

std::string NpyDoubles(const std::vector<double>& v, const std::vector<int>& shape) {
  return Npy("<f8", shape, Bytes(v));
}
std::string NpyInts(const std::vector<std::int32_t>& v, const std::vector<int>& shape) {
  return Npy("<i4", shape, Bytes(v));
}
std::string NpyBool(bool b) { return Npy("|b1", {}, std::string(1, b ? '\1' : '\0')); }
std::string NpyDouble(double d) { return NpyDoubles({d}, {}); }

// numpy's unicode strings: UTF-32LE, every element padded to the longest.
// The names here are ASCII (lens model names, file names are passed through
// byte by byte: a non-ASCII byte becomes the code point of that byte).
std::string NpyStrings(const std::vector<std::string>& strings, bool scalar) {
  std::size_t width = 1;
  for (const std::string& s : strings) width = std::max(width, s.size());
  std::string data;
  for (const std::string& s : strings) {
    for (std::size_t i = 0; i < width; ++i) {
      const unsigned char c = i < s.size() ? static_cast<unsigned char>(s[i]) : 0;
      data += static_cast<char>(c);
      data.append(3, '\0');
    }
  }
  const std::vector<int> shape =
      scalar ? std::vector<int>{} : std::vector<int>{static_cast<int>(strings.size())};
  return Npy("<U" + std::to_string(width), shape, data);
}
std::string NpyNone() { return NpyStrings({""}, true); }  // mrcal's None

void PutU16(std::string* out, unsigned v) {
  out->push_back(static_cast<char>(v & 0xff));
  out->push_back(static_cast<char>((v >> 8) & 0xff));
}
void PutU32(std::string* out, std::uint32_t v) {
  PutU16(out, v & 0xffff);
  PutU16(out, v >> 16);
}

// A zip archive of stored (uncompressed) members: local headers with the
// data, the central directory, the end record. No zip64: the archive stays
// far below 4 GB.
std::string Zip(const std::vector<std::pair<std::string, std::string>>& members) {
  std::string out, central;
  for (const auto& member : members) {
    // Named references, not a structured binding: clang 14 (the fuzz build)
    // cannot capture a binding in the lambda below.
    const std::string& name = member.first;
    const std::string& data = member.second;
    const std::uint32_t crc = Crc32(data);
    const std::uint32_t offset = static_cast<std::uint32_t>(out.size());
    const auto common = [&](std::string* s) {
      PutU16(s, 20);    // version needed: 2.0
      PutU16(s, 0);     // flags
      PutU16(s, 0);     // method: stored
      PutU16(s, 0);     // time
      PutU16(s, 0x21);  // date: 1980-01-01
      PutU32(s, crc);
      PutU32(s, static_cast<std::uint32_t>(data.size()));
      PutU32(s, static_cast<std::uint32_t>(data.size()));
      PutU16(s, static_cast<unsigned>(name.size()));
      PutU16(s, 0);  // extra length
    };
    PutU32(&out, 0x04034b50);
    common(&out);
    out += name;
    out += data;
    PutU32(&central, 0x02014b50);
    PutU16(&central, 20);  // made by
    common(&central);
    PutU16(&central, 0);  // comment length
    PutU16(&central, 0);  // disk
    PutU16(&central, 0);  // internal attributes
    PutU32(&central, 0);  // external attributes
    PutU32(&central, offset);
    central += name;
  }
  const std::uint32_t central_offset = static_cast<std::uint32_t>(out.size());
  out += central;
  PutU32(&out, 0x06054b50);
  PutU16(&out, 0);
  PutU16(&out, 0);
  PutU16(&out, static_cast<unsigned>(members.size()));
  PutU16(&out, static_cast<unsigned>(members.size()));
  PutU32(&out, static_cast<std::uint32_t>(central.size()));
  PutU32(&out, central_offset);
  PutU16(&out, 0);
  return out;
}

}  // namespace

std::uint32_t Crc32(const std::string& bytes) {
  // CRC-32 of zip (IEEE 802.3, reflected polynomial 0xEDB88320), bitwise.
  std::uint32_t crc = 0xffffffffu;
  for (const char ch : bytes) {
    crc ^= static_cast<unsigned char>(ch);
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

std::string Base85Encode(const std::string& bytes) {
  // Python's base64.b85encode (RFC 1924 alphabet): every 4 bytes, big-endian,
  // become 5 digits base 85, most significant first; a last group of n < 4
  // bytes is zero-padded and gives its first n + 1 digits.
  static constexpr char kAlphabet[] =
      "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz!#$%&()*+-;<=>?@^_`{|}~";
  std::string out;
  out.reserve(bytes.size() * 5 / 4 + 5);
  for (std::size_t i = 0; i < bytes.size(); i += 4) {
    const std::size_t n = std::min<std::size_t>(4, bytes.size() - i);
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      v = (v << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    }
    char digits[5];
    for (int k = 4; k >= 0; --k) {
      digits[k] = kAlphabet[v % 85];
      v /= 85;
    }
    out.append(digits, n + 1);
  }
  return out;
}

std::string MrcalOptimizationInputsBase85(const IntrinsicCalibration& cal) {
  const BoardGrid& grid = cal.grid;
  const int n_views = static_cast<int>(cal.views.size());
  const int n_grid = grid.width_n * grid.height_n;
  std::vector<double> frames, observations(static_cast<std::size_t>(n_views) * n_grid * 3, 0.0);
  std::vector<std::int32_t> indices;
  std::vector<std::string> paths;
  for (int i = 0; i < n_views; ++i) {
    const ViewResult& v = cal.views[i];
    frames.insert(frames.end(), v.rt_cam_board.begin(), v.rt_cam_board.end());
    for (int g = 0; g < n_grid; ++g)
      observations[(static_cast<std::size_t>(i) * n_grid + g) * 3 + 2] = -1.0;
    for (std::size_t j = 0; j < v.grid_index.size(); ++j) {
      double* o = &observations[(static_cast<std::size_t>(i) * n_grid + v.grid_index[j]) * 3];
      o[0] = v.observed_px[j].x();
      o[1] = v.observed_px[j].y();
      o[2] = v.outlier[j] ? -1.0 : 1.0;
    }
    indices.insert(indices.end(), {i, 0, -1});
    paths.push_back(v.name);
  }
  const std::vector<double>& intrinsics = cal.camera.intrinsics();
  const IntrinsicCalibrationOptions& o = cal.options;
  const bool has_distortion = intrinsics.size() > 4;
  std::vector<std::pair<std::string, std::string>> members = {
      {"intrinsics", NpyDoubles(intrinsics, {1, static_cast<int>(intrinsics.size())})},
      {"extrinsics_rt_fromref", NpyDoubles({}, {0, 6})},
      {"frames_rt_toref", NpyDoubles(frames, {n_views, 6})},
      {"points", NpyNone()},
      {"observations_board", NpyDoubles(observations, {n_views, grid.height_n, grid.width_n, 3})},
      {"indices_frame_camintrinsics_camextrinsics", NpyInts(indices, {n_views, 3})},
      {"observations_point", NpyNone()},
      {"indices_point_camintrinsics_camextrinsics", NpyNone()},
      {"lensmodel", NpyStrings({cal.camera.lens_model()}, true)},
      {"imagersizes", NpyInts({cal.camera.width_px(), cal.camera.height_px()}, {1, 2})},
      {"calobject_warp",
       cal.summary.board_warp_m
           ? NpyDoubles({(*cal.summary.board_warp_m)[0], (*cal.summary.board_warp_m)[1]}, {2})
           : NpyNone()},
      {"do_optimize_intrinsics_core", NpyBool(true)},
      {"do_optimize_intrinsics_distortions", NpyBool(has_distortion)},
      {"do_optimize_extrinsics", NpyBool(true)},
      {"do_optimize_frames", NpyBool(true)},
      {"do_optimize_calobject_warp", NpyBool(o.optimize_board_warp)},
      {"calibration_object_spacing", NpyDouble(grid.pitch_m)},
      {"do_apply_outlier_rejection", NpyBool(o.outlier_rejection)},
      {"do_apply_regularization", NpyBool(o.regularization)},
      {"verbose", NpyBool(false)},
      {"imagepaths", NpyStrings(paths, false)},
  };
  for (auto& m : members) m.first += ".npy";
  return Base85Encode(Zip(members));
}

}  // namespace groundline::calibration
