// Loop-closure search: an exact branch-and-bound correlative search of a scan
// over a window of a finished submap (Hess et al. 2016, "Real-time loop
// closure in 2D LIDAR SLAM", section V, Algorithm 3).
//
// Precomputed grids: level h holds, for each cell (x, y), the largest
// probability of the 2^h x 2^h block [x, x + 2^h) x [y, y + 2^h), so the
// score of a node of width 2^h (mean over the points of the level-h value at
// their cells) bounds the score of every offset it covers. Levels are built
// by doubling: M_{2w}(x, y) = max of M_w at (x, y), (x + w, y), (x, y + w),
// (x + w, y + w). Values are stored as bytes (probability * 255).
//
// The search is exact: the returned pose has the highest score of all
// discrete poses of the window (angle step: the angle that moves the
// farthest point by one cell; translation step: one cell) that score at
// least min_score, up to the byte rounding.
//
// Thread-safety: immutable after construction.
#ifndef GROUNDLINE_LOCALIZATION_LIDAR_LOOP_CLOSURE_H_
#define GROUNDLINE_LOCALIZATION_LIDAR_LOOP_CLOSURE_H_

#include <cstdint>
#include <optional>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/localization/lidar/probability_grid.h"

namespace groundline::localization::lidar {

struct BranchAndBoundOptions {
  double linear_window_m = 3.0;                                 // half width
  double angular_window_rad = 20.0 * 3.14159265358979 / 180.0;  // half width
  int depth = 7;         // levels: widths 1 .. 2^(depth-1) cells
  int max_points = 150;  // points used (evenly subsampled)
  // When > 0, also the best pose at least this far (translation) from the
  // best one that scores at least runner_up_min_ratio of it, at any angle:
  // BranchAndBoundMatch::runner_up. A place that repeats within the window
  // (the next bay of a rack aisle, the next aisle) has one; the best of two
  // near-equal scores is not evidence of which is right.
  double runner_up_distance_m = 0.0;
  double runner_up_min_ratio = 0.9;

  core::Status Validate() const;
};

class PrecomputedGrids {
 public:
  PrecomputedGrids(const ProbabilityGrid& grid, int depth);
  // Level-h value at cell (x, y) of the original grid, in [0, 1].
  float Value(int level, int x, int y) const { return ByteValue(level, x, y) * (1.0f / 255.0f); }
  // The same as stored: probability * 255, 0 off the grid.
  int ByteValue(int level, int x, int y) const {
    const Level& l = levels_[static_cast<std::size_t>(level)];
    const int ix = x + l.width - 1, iy = y + l.width - 1;
    if (ix < 0 || iy < 0 || ix >= l.size_x || iy >= l.size_y) return 0;
    return l.values[static_cast<std::size_t>(iy) * l.size_x + ix];
  }
  int depth() const { return static_cast<int>(levels_.size()); }

 private:
  struct Level {
    int width = 0;   // of the block
    int size_x = 0;  // stored cells: x in [-(width - 1), grid width)
    int size_y = 0;
    std::vector<uint8_t> values;
  };
  std::vector<Level> levels_;
};

struct BranchAndBoundPose {
  core::SE2 T_grid_base;
  double score = 0.0;  // mean probability, [0, 1]
};

struct BranchAndBoundMatch {
  core::SE2 T_grid_base;
  double score = 0.0;  // mean probability, [0, 1]
  // See BranchAndBoundOptions::runner_up_distance_m; nullopt when not
  // searched or none scores high enough.
  std::optional<BranchAndBoundPose> runner_up;
};

// The best pose in the window around `center` (T_grid_base) with score >=
// min_score, or nullopt; and its runner-up (options.runner_up_distance_m). `grid` is the grid
// `precomputed` was built from.
std::optional<BranchAndBoundMatch> BranchAndBoundSearch(
    const ProbabilityGrid& grid, const PrecomputedGrids& precomputed,
    const std::vector<core::Vector2>& points_base_m, const core::SE2& center, double min_score,
    const BranchAndBoundOptions& options);

}  // namespace groundline::localization::lidar

#endif  // GROUNDLINE_LOCALIZATION_LIDAR_LOOP_CLOSURE_H_
