#include "groundline/core/trajectory_io.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <string_view>

#include "groundline/core/atomic_file.h"
#include "groundline/core/text_parse.h"

namespace groundline::core {
namespace {

constexpr double kUnitQuaternionTolerance = 1e-3;
constexpr char kEurocHeader[] =
    "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],"
    "q_RS_z []";

// Fields of one pose line, in TUM order: t x y z qx qy qz qw.
using PoseFields = std::array<double, 8>;
constexpr std::array<const char*, 8> kTumFieldNames = {"t", "x", "y", "z", "qx", "qy", "qz", "qw"};

Result<StampedPose> PoseFromFields(const PoseFields& f, const std::string& file, std::size_t line) {
  const double qx = f[4], qy = f[5], qz = f[6], qw = f[7];
  const double norm = std::sqrt(qx * qx + qy * qy + qz * qz + qw * qw);
  if (std::abs(norm - 1.0) > kUnitQuaternionTolerance) {
    return Status::Error(FieldError(file, line, "quaternion", "a unit quaternion (norm 1 +- 1e-3)",
                                    "norm " + std::to_string(norm)));
  }
  // Homogeneous form of the ZYX yaw, so that the accepted slack in the norm
  // does not bias the angle (1 - 2(qy^2 + qz^2) assumes |q| = 1 exactly).
  const double yaw = std::atan2(2.0 * (qw * qz + qx * qy), qw * qw + qx * qx - qy * qy - qz * qz);
  StampedPose pose;
  pose.stamp_s = f[0];
  pose.pose = SE2(f[1], f[2], yaw);
  return pose;
}

// Parses tokens into fields, naming the offending one; `names` in token order.
Status ParseFields(const std::vector<std::string_view>& tokens,
                   const std::array<const char*, 8>& names, const std::string& file,
                   std::size_t line, PoseFields* fields) {
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::optional<double> value = ParseDouble(tokens[i]);
    if (!value || !std::isfinite(*value)) {
      return Status::Error(FieldError(file, line, names[i], "a finite number", tokens[i]));
    }
    (*fields)[i] = *value;
  }
  return Status::Ok();
}

Status AppendChecked(Trajectory* trajectory, StampedPose pose, const std::string& file,
                     std::size_t line, std::string_view stamp_field) {
  if (!trajectory->empty() && !(pose.stamp_s > trajectory->back().stamp_s)) {
    char got[96];
    std::snprintf(got, sizeof(got), "%.9f after %.9f", pose.stamp_s, trajectory->back().stamp_s);
    return Status::Error(FieldError(file, line, stamp_field, "strictly increasing stamps", got));
  }
  trajectory->push_back(std::move(pose));
  return Status::Ok();
}

void QuaternionFromYaw(double yaw, double* qz, double* qw) {
  *qz = std::sin(0.5 * yaw);
  *qw = std::cos(0.5 * yaw);
}

}  // namespace

Result<Trajectory> ReadTumTrajectory(const std::filesystem::path& path) {
  std::ifstream in(path);
  const std::string file = path.string();
  if (!in) return Status::Error("cannot open TUM trajectory " + file);
  Trajectory trajectory;
  std::string text;
  std::size_t line = 0;
  while (std::getline(in, text)) {
    ++line;
    const std::vector<std::string_view> tokens = SplitWhitespace(text);
    if (tokens.empty() || tokens.front().front() == '#') continue;
    if (tokens.size() != 8) {
      return Status::Error(FieldError(file, line, "line", "8 fields 't x y z qx qy qz qw'",
                                      std::to_string(tokens.size()) + " fields"));
    }
    PoseFields fields{};
    if (Status s = ParseFields(tokens, kTumFieldNames, file, line, &fields); !s.ok()) return s;
    Result<StampedPose> pose = PoseFromFields(fields, file, line);
    if (!pose.ok()) return pose.status();
    if (Status s = AppendChecked(&trajectory, std::move(pose).value(), file, line, "t"); !s.ok()) {
      return s;
    }
  }
  if (in.bad()) return Status::Error("read error in " + file);
  return trajectory;
}

std::string FormatTumLine(const StampedPose& p) {
  char buffer[256];
  double qz = 0.0, qw = 1.0;
  QuaternionFromYaw(p.pose.yaw(), &qz, &qw);
  std::snprintf(buffer, sizeof(buffer), "%.9f %.9f %.9f 0 0 0 %.12f %.12f\n", p.stamp_s, p.pose.x(),
                p.pose.y(), qz, qw);
  return buffer;
}

Status WriteTumTrajectory(const std::filesystem::path& path, const Trajectory& trajectory) {
  if (Status s = ValidateTrajectory(trajectory, path.string()); !s.ok()) return s;
  return WriteFileAtomically(path, [&trajectory](std::ostream& out) {
    for (const StampedPose& p : trajectory) out << FormatTumLine(p);
    return Status::Ok();
  });
}

Result<Trajectory> ReadEurocTrajectory(const std::filesystem::path& path) {
  std::ifstream in(path);
  const std::string file = path.string();
  if (!in) return Status::Error("cannot open EuRoC trajectory " + file);
  // EuRoC column order: t[ns] px py pz qw qx qy qz; map onto TUM field order.
  constexpr std::array<const char*, 8> kNames = {
      "timestamp [ns]", "p_RS_R_x", "p_RS_R_y", "p_RS_R_z", "q_RS_w", "q_RS_x", "q_RS_y", "q_RS_z"};
  Trajectory trajectory;
  std::string text;
  std::size_t line = 0;
  while (std::getline(in, text)) {
    ++line;
    const std::string_view trimmed = Trim(text);
    if (trimmed.empty() || trimmed.front() == '#') continue;
    const std::vector<std::string_view> tokens = SplitDelimited(trimmed, ',');
    if (tokens.size() < 8) {
      return Status::Error(FieldError(file, line, "line", "at least 8 comma-separated fields",
                                      std::to_string(tokens.size()) + " fields"));
    }
    const std::optional<std::int64_t> stamp_ns = ParseInt(tokens[0]);
    if (!stamp_ns) {
      return Status::Error(FieldError(file, line, kNames[0], "an integer", tokens[0]));
    }
    PoseFields euroc{};
    euroc[0] = 0.0;
    for (std::size_t i = 1; i < 8; ++i) {
      const std::optional<double> value = ParseDouble(tokens[i]);
      if (!value || !std::isfinite(*value)) {
        return Status::Error(FieldError(file, line, kNames[i], "a finite number", tokens[i]));
      }
      euroc[i] = *value;
    }
    const PoseFields tum = {static_cast<double>(*stamp_ns) * 1e-9,
                            euroc[1],
                            euroc[2],
                            euroc[3],
                            euroc[5],
                            euroc[6],
                            euroc[7],
                            euroc[4]};
    Result<StampedPose> pose = PoseFromFields(tum, file, line);
    if (!pose.ok()) return pose.status();
    if (Status s = AppendChecked(&trajectory, std::move(pose).value(), file, line, kNames[0]);
        !s.ok()) {
      return s;
    }
  }
  if (in.bad()) return Status::Error("read error in " + file);
  return trajectory;
}

Status WriteEurocTrajectory(const std::filesystem::path& path, const Trajectory& trajectory) {
  if (Status s = ValidateTrajectory(trajectory, path.string()); !s.ok()) return s;
  return WriteFileAtomically(path, [&trajectory](std::ostream& out) {
    out << kEurocHeader << "\n";
    char buffer[256];
    for (const StampedPose& p : trajectory) {
      double qz = 0.0, qw = 1.0;
      QuaternionFromYaw(p.pose.yaw(), &qz, &qw);
      const long long stamp_ns = std::llround(p.stamp_s * 1e9);
      std::snprintf(buffer, sizeof(buffer), "%lld,%.9f,%.9f,0,%.12f,0,0,%.12f\n", stamp_ns,
                    p.pose.x(), p.pose.y(), qw, qz);
      out << buffer;
    }
    return Status::Ok();
  });
}

TrajectoryFormat GuessTrajectoryFormat(const std::filesystem::path& path) {
  return path.extension() == ".csv" ? TrajectoryFormat::kEuroc : TrajectoryFormat::kTum;
}

Result<Trajectory> ReadTrajectory(const std::filesystem::path& path) {
  return GuessTrajectoryFormat(path) == TrajectoryFormat::kEuroc ? ReadEurocTrajectory(path)
                                                                 : ReadTumTrajectory(path);
}

Status WriteTrajectory(const std::filesystem::path& path, const Trajectory& trajectory,
                       TrajectoryFormat format) {
  return format == TrajectoryFormat::kEuroc ? WriteEurocTrajectory(path, trajectory)
                                            : WriteTumTrajectory(path, trajectory);
}

Status ValidateTrajectory(const Trajectory& trajectory, const std::string& name) {
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    const StampedPose& p = trajectory[i];
    if (!std::isfinite(p.stamp_s) || !std::isfinite(p.pose.x()) || !std::isfinite(p.pose.y()) ||
        !std::isfinite(p.pose.yaw())) {
      return Status::Error(name + ": pose " + std::to_string(i) + " has a non-finite value");
    }
    if (i > 0 && !(p.stamp_s > trajectory[i - 1].stamp_s)) {
      return Status::Error(name + ": pose " + std::to_string(i) +
                           ": stamps must increase strictly");
    }
  }
  return Status::Ok();
}

}  // namespace groundline::core
