// Reader for the ground-truth relations of Kuemmerle et al. 2009, "On
// measuring the accuracy of SLAM algorithms" (.relations files of the
// Freiburg SLAM evaluation; plain, gzip or bzip2).
//
// One relation per line, whitespace-separated:
//   t1 t2 x y z roll pitch yaw
// t1, t2 are the ipc_timestamps [s] of two laser scans of the matching CARMEN
// log (they match FLASER ipc_timestamps to within 5e-6 s in aces and
// mit-csail); (x [m], y [m], yaw [rad]) is the pose at t2 expressed in the
// frame of the pose at t1, i.e. delta = T_w_1^-1 * T_w_2, read as
// SE2(x, y, yaw), so yaw is wrapped to [-pi, pi]. The data are planar: z,
// roll and pitch must be 0 within `max_out_of_plane` (an error otherwise, so
// that a 3-D file is not silently flattened).
// Blank lines and lines starting with '#' are skipped. Every other line must
// have exactly 8 finite numbers; errors name "path:line: field 'name' (field
// k)". Relations are returned in file order (not sorted: the files mix short
// and loop-closing relations).
#ifndef GROUNDLINE_IO_RELATIONS_H_
#define GROUNDLINE_IO_RELATIONS_H_

#include <filesystem>
#include <vector>

#include "groundline/core/status.h"
#include "groundline/core/trajectory.h"

namespace groundline::io {

struct RelationsReadOptions {
  // Largest |z| [m], |roll| and |pitch| [rad] accepted as planar.
  double max_out_of_plane = 1e-9;

  core::Status Validate() const;
};

core::Result<std::vector<core::Relation>> ReadRelations(const std::filesystem::path& path,
                                                        const RelationsReadOptions& options = {});

}  // namespace groundline::io

#endif  // GROUNDLINE_IO_RELATIONS_H_
