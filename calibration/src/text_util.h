// Small text helpers shared by the calibration file readers and writers.
#ifndef GROUNDLINE_CALIBRATION_SRC_TEXT_UTIL_H_
#define GROUNDLINE_CALIBRATION_SRC_TEXT_UTIL_H_

#include <array>
#include <cassert>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

#include "groundline/core/status.h"

namespace groundline::calibration::text_util {

// The shortest decimal text that parses back to exactly `value` (std::to_chars).
inline std::string ShortestDecimal(double value) {
  std::array<char, 64> buffer{};
  const auto [end, ec] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  assert(ec == std::errc());
  (void)ec;
  return std::string(buffer.data(), end);
}

// ShortestDecimal, with ".0" put before a bare exponent ("9e-04" -> "9.0e-04"):
// YAML 1.1 readers such as PyYAML (ROS' Python tools) take "9e-04" for a string.
inline std::string YamlDecimal(double value) {
  std::string text = ShortestDecimal(value);
  const size_t e = text.find('e');
  if (e != std::string::npos && text.find('.') == std::string::npos) text.insert(e, ".0");
  return text;
}

// The whole file as text; `what` names the kind of file in the error message.
inline core::Result<std::string> ReadTextFile(const std::filesystem::path& path,
                                              const std::string& what) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    return core::Status::Error(path.string() + ": no such " + what + " (not a regular file)");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) return core::Status::Error(path.string() + ": cannot open the " + what + " for reading");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return core::Status::Error(path.string() + ": read error");
  return text.str();
}

}  // namespace groundline::calibration::text_util

#endif  // GROUNDLINE_CALIBRATION_SRC_TEXT_UTIL_H_
