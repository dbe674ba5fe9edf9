// Calibration targets: the boards and sheets of calib_targets/targets.yaml
// (format groundline-calib-targets, version 1), and the corner grid a board
// gives the intrinsic solver.
//
// Units: metres. Board frame: origin at the first corner the detector reports
// (top-left of the printed board), x to the right along a printed row, y down
// the printed page, z into the board (right-handed; a camera in front of the
// board sees z > 0 away from it).
//
// Types:
//   chessboard       inner_corners_x x inner_corners_y inner corners, square_m.
//   aprilgrid        tags_x x tags_y tag36h11 tags, ids row-major from the
//                    top-left starting at first_id (default 0); tag_size_m is
//                    the black border's outer width (the AprilTag convention);
//                    the gap between tags is spacing_ratio * tag_size_m.
//   floor_tag_sheet  one tag per sheet (ids first_id .. first_id+count-1),
//                    tag_size_m as above, paper A4 or A3; used on the floor by
//                    the floor-extrinsics calibration, printed here.
//
// The solver (mrcal) takes a board as a regular grid of width_n x height_n
// points at one pitch. A chessboard is that grid. An AprilGrid's tag corners
// are on a regular grid of pitch tag_size / n where n is the smallest integer
// <= 100 that makes the gap an integer multiple of the pitch too
// (spacing_ratio 0.3 -> pitch = tag_size / 10); the grid points between
// corners are never observed (the solver is told they are outliers).
#ifndef GROUNDLINE_CALIBRATION_CALIB_TARGET_H_
#define GROUNDLINE_CALIBRATION_CALIB_TARGET_H_

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "groundline/core/status.h"

namespace groundline::calibration {

enum class TargetType { kChessboard, kAprilGrid, kFloorTagSheet };

struct CalibTarget {
  std::string name;
  TargetType type = TargetType::kChessboard;
  // chessboard
  int inner_corners_x = 0;
  int inner_corners_y = 0;
  double square_m = 0.0;
  // aprilgrid and floor_tag_sheet
  std::string family = "tag36h11";
  int tags_x = 0;
  int tags_y = 0;
  double tag_size_m = 0.0;
  double spacing_ratio = 0.0;
  int first_id = 0;
  int count = 0;      // floor_tag_sheet: number of sheets
  std::string paper;  // floor_tag_sheet: "A4" or "A3"; boards: optional, "" = auto

  bool IsBoard() const { return type != TargetType::kFloorTagSheet; }
  // Outer size of the printed pattern (boards: the squares including the outer
  // ring of a chessboard; aprilgrid: first tag edge to last tag edge), m.
  Eigen::Vector2d PatternSize_m() const;
};

const char* TargetTypeName(TargetType type);

// The regular grid the solver sees (see the file comment).
struct BoardGrid {
  int width_n = 0;     // points along x
  int height_n = 0;    // points along y
  double pitch_m = 0;  // distance between neighbouring grid points
  // Grid index (row-major: iy * width_n + ix) of every point the detector can
  // report, in the order the detector reports them.
  std::vector<int> observable;
  // Position of grid index i in the board frame (z = 0), m.
  Eigen::Vector3d Point_board(int index) const;
};

// Asserts target.IsBoard() (and the definition having passed validation).
BoardGrid MakeBoardGrid(const CalibTarget& target);

// Grid index of corner k (0..3, in libapriltag's order: bottom-left,
// bottom-right, top-right, top-left of the printed tag) of the aprilgrid tag
// with this id, or -1 when the id is not on the board.
int AprilGridCornerIndex(const CalibTarget& target, const BoardGrid& grid, int tag_id, int k);

// Reads and validates targets.yaml. Errors name the file, the target and the
// field ("targets.yaml: target 'x': field 'square_m': expected > 0, got -1").
core::Result<std::vector<CalibTarget>> ReadCalibTargets(const std::filesystem::path& path);
core::Result<std::vector<CalibTarget>> ParseCalibTargets(const std::string& yaml_text,
                                                         const std::string& source_name);
// The target of that name, or an error listing the names available.
core::Result<CalibTarget> FindCalibTarget(const std::vector<CalibTarget>& targets,
                                          std::string_view name);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_CALIB_TARGET_H_
