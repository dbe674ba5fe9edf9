#include "groundline/core/trajectory_covariance_io.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "groundline/core/atomic_file.h"
#include "groundline/core/text_parse.h"

namespace groundline::core {
namespace {

constexpr double kStampToleranceS = 1e-6;
constexpr std::array<const char*, 7> kFieldNames = {"t",    "c_xx",   "c_xy",    "c_xyaw",
                                                    "c_yy", "c_yyaw", "c_yawyaw"};

}  // namespace

Status WriteTrajectoryCovariances(const std::filesystem::path& path, const Trajectory& trajectory) {
  return WriteFileAtomically(path, [&trajectory](std::ostream& out) {
    out << "# t c_xx c_xy c_xyaw c_yy c_yyaw c_yawyaw (tangent x_m y_m yaw_rad)\n";
    char buffer[256];
    for (const StampedPose& p : trajectory) {
      if (!p.covariance) continue;
      const Matrix3& c = *p.covariance;
      std::snprintf(buffer, sizeof(buffer), "%.9f %.9e %.9e %.9e %.9e %.9e %.9e\n", p.stamp_s,
                    c(0, 0), c(0, 1), c(0, 2), c(1, 1), c(1, 2), c(2, 2));
      out << buffer;
    }
    return Status::Ok();
  });
}

Status AttachTrajectoryCovariances(const std::filesystem::path& path, Trajectory* trajectory) {
  std::ifstream in(path);
  const std::string file = path.string();
  if (!in) return Status::Error("cannot open covariance file " + file);
  std::string text;
  std::size_t line = 0;
  double previous_s = -INFINITY;
  while (std::getline(in, text)) {
    ++line;
    const std::vector<std::string_view> tokens = SplitWhitespace(text);
    if (tokens.empty() || tokens.front().front() == '#') continue;
    if (tokens.size() != kFieldNames.size()) {
      return Status::Error(FieldError(file, line, "line",
                                      "7 fields 't c_xx c_xy c_xyaw c_yy c_yyaw c_yawyaw'",
                                      std::to_string(tokens.size()) + " fields"));
    }
    std::array<double, 7> f{};
    for (std::size_t i = 0; i < f.size(); ++i) {
      const std::optional<double> value = ParseDouble(tokens[i]);
      if (!value || !std::isfinite(*value)) {
        return Status::Error(FieldError(file, line, kFieldNames[i], "a finite number", tokens[i]));
      }
      f[i] = *value;
    }
    if (!(f[0] > previous_s)) {
      return Status::Error(
          FieldError(file, line, "t", "strictly increasing stamps", std::string(tokens[0])));
    }
    previous_s = f[0];
    const auto it =
        std::lower_bound(trajectory->begin(), trajectory->end(), f[0] - kStampToleranceS,
                         [](const StampedPose& p, double t) { return p.stamp_s < t; });
    if (it == trajectory->end() || std::abs(it->stamp_s - f[0]) > kStampToleranceS) {
      return Status::Error(
          FieldError(file, line, "t", "the stamp of a trajectory pose", std::string(tokens[0])));
    }
    Matrix3 c;
    c << f[1], f[2], f[3], f[2], f[4], f[5], f[3], f[5], f[6];
    it->covariance = c;
  }
  if (in.bad()) return Status::Error("read error in " + file);
  return Status::Ok();
}

}  // namespace groundline::core
