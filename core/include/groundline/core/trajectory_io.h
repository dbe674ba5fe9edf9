// Trajectory files in the two formats the evo tool reads.
//
// TUM: one pose per line, "t x y z qx qy qz qw", whitespace separated, t in
//   seconds, '#' starts a comment line. Written with z = 0 and a pure yaw
//   quaternion; read by projecting onto the plane (yaw of the quaternion,
//   z ignored), since every groundline trajectory is planar.
// EuRoC: CSV with the header
//   "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z
//   []" (the layout of EuRoC's state_groundtruth_estimate0/data.csv), t in integer nanoseconds;
//   extra columns after the eighth are ignored on reading.
//
// Readers validate: every field a finite number, the quaternion of unit norm
// (within 1e-3), stamps strictly increasing. Errors name file, line and field.
// Writers write atomically.
#ifndef GROUNDLINE_CORE_TRAJECTORY_IO_H_
#define GROUNDLINE_CORE_TRAJECTORY_IO_H_

#include <filesystem>
#include <string>

#include "groundline/core/status.h"
#include "groundline/core/trajectory.h"

namespace groundline::core {

enum class TrajectoryFormat { kTum, kEuroc };

Result<Trajectory> ReadTumTrajectory(const std::filesystem::path& path);
Status WriteTumTrajectory(const std::filesystem::path& path, const Trajectory& trajectory);
// One TUM line ("t x y 0 0 0 qz qw\n", as WriteTumTrajectory writes it), for
// writers that stream a trajectory.
std::string FormatTumLine(const StampedPose& pose);

Result<Trajectory> ReadEurocTrajectory(const std::filesystem::path& path);
Status WriteEurocTrajectory(const std::filesystem::path& path, const Trajectory& trajectory);

// EuRoC for a ".csv" file, TUM otherwise.
TrajectoryFormat GuessTrajectoryFormat(const std::filesystem::path& path);
Result<Trajectory> ReadTrajectory(const std::filesystem::path& path);
Status WriteTrajectory(const std::filesystem::path& path, const Trajectory& trajectory,
                       TrajectoryFormat format);

// Checks that stamps are finite and strictly increasing and poses finite.
// `name` prefixes the message (a file name, or "estimate").
Status ValidateTrajectory(const Trajectory& trajectory, const std::string& name);

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_TRAJECTORY_IO_H_
