// A probability occupancy grid in the plane, the map of one LiDAR submap.
//
// Cells are square (resolution_m, 5 cm by default). Cell (ix, iy) covers
// [origin_x + ix * res, origin_x + (ix + 1) * res) x [same in y], in the
// frame the grid is written in (the submap frame). Its centre is at
// origin + (i + 0.5) * res. Storage is row-major, row = iy.
//
// Each cell keeps the log-odds l = log(p / (1 - p)) of being occupied, or
// "unknown" before its first observation. InsertScan() updates the cells of
// one scan once each (Thrun et al., Probabilistic Robotics, eq. 9.7):
//   hit cell (contains a return):        l += logit(hit_probability)
//   miss cell (a ray passes through it):  l += logit(miss_probability)
// where an unknown cell starts at l = 0, and l is clamped to
// [logit(min_probability), logit(max_probability)] so that a cell stays able
// to change (a pallet that leaves). A cell hit in a scan is not also missed
// by that scan. Rays are traced with Bresenham's line between the cell of
// the sensor and the cell of the return.
//
// The grid grows (doubling its size in the needed direction) when a scan
// reaches past its limits, so a submap needs no a-priori extent.
//
// Probability() reads unknown cells as min_probability (Cartographer reads
// them as "no correspondence"), which is what the matchers want: a point
// may not sit on cells nothing was ever seen in.
//
// Not thread-safe for writing; const reads may run concurrently.
#ifndef GROUNDLINE_LOCALIZATION_LIDAR_PROBABILITY_GRID_H_
#define GROUNDLINE_LOCALIZATION_LIDAR_PROBABILITY_GRID_H_

#include <cstdint>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"

namespace groundline::localization::lidar {

struct ProbabilityGridOptions {
  double resolution_m = 0.05;
  double hit_probability = 0.55;
  double miss_probability = 0.49;
  double min_probability = 0.1;
  double max_probability = 0.9;

  core::Status Validate() const;
};

// Integer cell index.
struct CellIndex {
  int x = 0;
  int y = 0;
};

// Visits the cells of Bresenham's line from `from` to `to` in order,
// both included, calling visit(CellIndex) until it returns false.
template <typename Visit>
void ForEachCellOnLine(const CellIndex& from, const CellIndex& to, Visit&& visit) {
  int x = from.x, y = from.y;
  const int dx = to.x > x ? to.x - x : x - to.x, dy = -(to.y > y ? to.y - y : y - to.y);
  const int sx = x < to.x ? 1 : -1, sy = y < to.y ? 1 : -1;
  int err = dx + dy;
  while (true) {
    if (!visit(CellIndex{x, y})) return;
    if (x == to.x && y == to.y) return;
    const int e2 = 2 * err;
    if (e2 >= dy) err += dy, x += sx;
    if (e2 <= dx) err += dx, y += sy;
  }
}

class ProbabilityGrid {
 public:
  // An empty grid of width x height cells whose corner is at origin_m.
  ProbabilityGrid(const ProbabilityGridOptions& options, const core::Vector2& origin_m,
                  int width = 64, int height = 64);

  // Inserts one scan: sensor origin and returns (hits), both in the grid
  // frame, metres. Free space along each ray is traced up to the return.
  // `misses_only` are end points of rays without a return (traced as free
  // space to the end point, no hit).
  void InsertScan(const core::Vector2& sensor_origin_m, const std::vector<core::Vector2>& hits_m,
                  const std::vector<core::Vector2>& misses_only_m = {});

  // The cell containing point_m (may be outside the grid).
  CellIndex CellOf(const core::Vector2& point_m) const;
  bool Contains(const CellIndex& cell) const {
    return cell.x >= 0 && cell.y >= 0 && cell.x < width_ && cell.y < height_;
  }
  bool IsKnown(const CellIndex& cell) const;
  // The cell and its 8 neighbours are known and below free_probability:
  // space the grid has seen through, with nothing occupied within one cell.
  bool IsFreeAround(const CellIndex& cell, double free_probability) const;
  // Occupancy probability; min_probability for unknown or outside cells.
  double Probability(const CellIndex& cell) const {
    return Contains(cell) ? CellProbability(Index(cell)) : options_.min_probability;
  }

  // Probability of every cell, row-major (height rows of width values),
  // unknown = min_probability. Empty after Compress() (use Probability()).
  const std::vector<float>& probabilities() const { return probability_; }

  // Shrinks the grid to the bounding box of its known cells (one cell of
  // margin), e.g. when a submap is finished.
  void CropToKnown();
  // For a grid that will not change again (a finished submap): keeps each
  // cell's probability in 16 bits (0 = unknown; 1..65535 spans [0, 1], an
  // error below 1e-5) and drops the update state, 2 bytes per cell instead
  // of 12. Probability() and IsKnown() keep working (to that precision);
  // InsertScan() must not be called again.
  void Compress();
  bool compressed() const { return compressed_; }

  int width() const { return width_; }
  int height() const { return height_; }
  double resolution_m() const { return options_.resolution_m; }
  const core::Vector2& origin_m() const { return origin_m_; }
  const ProbabilityGridOptions& options() const { return options_; }
  int known_cells() const { return known_cells_; }

 private:
  // Grows the grid so that both corners' cells are inside.
  void GrowToContain(const core::Vector2& min_m, const core::Vector2& max_m);
  void Update(int index, float delta_log_odds);
  double CellProbability(std::size_t index) const {
    if (!compressed_) return probability_[index];
    const uint16_t v = compressed_probability_[index];
    return v == 0 ? options_.min_probability : (v - 1) * (1.0 / 65534.0);
  }
  std::size_t Index(const CellIndex& c) const {
    return static_cast<std::size_t>(c.y) * static_cast<std::size_t>(width_) +
           static_cast<std::size_t>(c.x);
  }

  ProbabilityGridOptions options_;
  core::Vector2 origin_m_;
  int width_ = 0;
  int height_ = 0;
  int known_cells_ = 0;
  float hit_log_odds_ = 0.0f, miss_log_odds_ = 0.0f, min_log_odds_ = 0.0f, max_log_odds_ = 0.0f;
  std::vector<float> log_odds_;      // NaN = unknown
  std::vector<float> probability_;   // derived from log_odds_
  std::vector<uint32_t> last_scan_;  // the scan that last updated a cell
  uint32_t scan_count_ = 0;
  bool compressed_ = false;
  std::vector<uint16_t> compressed_probability_;  // after Compress(): 0 = unknown
};

}  // namespace groundline::localization::lidar

#endif  // GROUNDLINE_LOCALIZATION_LIDAR_PROBABILITY_GRID_H_
