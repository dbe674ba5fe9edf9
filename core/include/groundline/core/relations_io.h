// Reading Kuemmerle relation files (the ground truth of the Freiburg SLAM
// evaluation, e.g. shared/data/lidar2d/aces.relations).
//
// One relation per line, whitespace separated: "t1 t2 x y z roll pitch yaw",
// the pose at t2 expressed in the frame of the pose at t1 (metres, radians,
// stamps in seconds of the log's ipc_timestamp clock). Blank lines and lines
// starting with '#' are skipped. The relations are planar: z is ignored, roll
// and pitch must be within 1e-3 rad of zero (else an error names the line).
// Every field must be a finite number. Order is kept as in the file.
//
// This is the core's small reader used by `groundline eval`; it has no
// dependency on the io module's log readers.
#ifndef GROUNDLINE_CORE_RELATIONS_IO_H_
#define GROUNDLINE_CORE_RELATIONS_IO_H_

#include <filesystem>
#include <vector>

#include "groundline/core/status.h"
#include "groundline/core/trajectory.h"

namespace groundline::core {

Result<std::vector<Relation>> ReadRelations(const std::filesystem::path& path);

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_RELATIONS_IO_H_
