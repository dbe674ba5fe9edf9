#include "groundline/service/service_state.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>

#include "groundline/core/atomic_file.h"
#include "groundline/core/covariance.h"
#include "groundline/core/json_fields.h"

namespace groundline::service {

core::Result<SavedState> ReadServiceState(const std::filesystem::path& path) {
  const std::string hint = "; delete it or set start.resume: false";
  nlohmann::json root;
  if (core::Status s = core::ReadJsonFile(path, "service's saved state", &root); !s.ok()) {
    return core::Status::Error(s.message() + hint);
  }
  core::JsonFieldReader reader(path.string());
  SavedState state;
  state.stamp_s = reader.Finite(root, "", "stamp_s");
  const double x = reader.Finite(root, "", "x_m");
  const double y = reader.Finite(root, "", "y_m");
  const double yaw = reader.Finite(root, "", "yaw_rad");
  const std::vector<double> cov = reader.Numbers(root, "", "cov", 9);
  if (!reader.ok()) return core::Status::Error(reader.status().message() + hint);
  state.T_map_base = core::SE2(x, y, yaw);
  for (int i = 0; i < 9; ++i) state.covariance(i / 3, i % 3) = cov[i];
  if (!core::IsCovariance(state.covariance)) {
    return core::Status::Error(path.string() +
                               ": field 'cov': expected a symmetric positive definite 3x3 "
                               "covariance (9 numbers, row-major)" +
                               hint);
  }
  return state;
}

core::Status WriteServiceState(const std::filesystem::path& path, const SavedState& state) {
  nlohmann::ordered_json j = {{"stamp_s", state.stamp_s},
                              {"x_m", state.T_map_base.x()},
                              {"y_m", state.T_map_base.y()},
                              {"yaw_rad", state.T_map_base.yaw()},
                              {"cov", nlohmann::ordered_json::array()}};
  for (int i = 0; i < 9; ++i) j["cov"].push_back(state.covariance(i / 3, i % 3));
  return core::WriteFileAtomically(path, j.dump(2) + "\n");
}

namespace {

// The stamp of one whole line, or nothing for a line that is not one.
std::optional<double> LineStamp(const std::string& line, StreamedFormat format) {
  if (format == StreamedFormat::kTum) {
    const char* begin = line.c_str();
    char* end = nullptr;
    const double t = std::strtod(begin, &end);
    if (end == begin || !std::isfinite(t)) return std::nullopt;
    return t;
  }
  const nlohmann::json j = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
  if (!j.is_object()) return std::nullopt;
  const auto it = j.find("stamp_s");
  if (it == j.end() || !it->is_number()) return std::nullopt;
  return it->get<double>();
}

}  // namespace

core::Result<int> TrimStreamedOutput(const std::filesystem::path& path, StreamedFormat format,
                                     double stamp_s) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) return core::Status::Error(path.string() + ": cannot read the run output to resume it");
  std::ostringstream kept;
  int removed = 0;
  std::string line;
  while (std::getline(in, line)) {
    // A last line without its newline was cut by a kill.
    const bool whole = !in.eof();
    const std::optional<double> t = whole ? LineStamp(line, format) : std::nullopt;
    if (whole && (line.empty() || line[0] == '#')) {
      kept << line << '\n';  // comments and blank lines stay
    } else if (t && *t <= stamp_s) {
      kept << line << '\n';
    } else {
      ++removed;
    }
  }
  if (removed == 0) return 0;
  if (core::Status s = core::WriteFileAtomically(path, kept.str()); !s.ok()) return s;
  return removed;
}

}  // namespace groundline::service
