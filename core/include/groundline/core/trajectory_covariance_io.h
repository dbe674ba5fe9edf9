// The covariance side file of a trajectory: TUM files carry no covariance, so
// `groundline localize` writes OUT/trajectory_covariance.txt next to
// OUT/trajectory.tum and `groundline eval` attaches it for the NEES.
//
// Format: one pose per line, "t c_xx c_xy c_xyaw c_yy c_yyaw c_yawyaw",
// whitespace separated: t in seconds (the pose's stamp in the TUM file), then
// the upper triangle of the 3x3 covariance in the tangent space (x_m, y_m,
// yaw_rad) of trajectory.h (right perturbation), in m^2, m rad, rad^2.
// '#' starts a comment line. Stamps strictly increasing; only poses that
// carry a covariance are written.
#ifndef GROUNDLINE_CORE_TRAJECTORY_COVARIANCE_IO_H_
#define GROUNDLINE_CORE_TRAJECTORY_COVARIANCE_IO_H_

#include <filesystem>

#include "groundline/core/status.h"
#include "groundline/core/trajectory.h"

namespace groundline::core {

// Writes atomically the covariance of every pose that has one.
Status WriteTrajectoryCovariances(const std::filesystem::path& path, const Trajectory& trajectory);

// Reads the file and sets the covariance of each pose of *trajectory whose
// stamp is within 1e-6 s of a line's stamp. Errors name file, line and field:
// a malformed line, a non-finite value, unsorted stamps, a stamp that matches
// no pose. Poses without a line keep their covariance (or none).
Status AttachTrajectoryCovariances(const std::filesystem::path& path, Trajectory* trajectory);

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_TRAJECTORY_COVARIANCE_IO_H_
