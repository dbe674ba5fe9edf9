#include "groundline/localization/lidar/loop_closure.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace groundline::localization::lidar {

core::Status BranchAndBoundOptions::Validate() const {
  if (!(linear_window_m >= 0.0 && angular_window_rad >= 0.0 &&
        angular_window_rad <= std::numbers::pi)) {
    return core::Status::Error("need linear_window_m >= 0 and angular_window_rad in [0, pi]");
  }
  if (depth < 1 || depth > 12) return core::Status::Error("depth must be in [1, 12]");
  if (max_points < 1) return core::Status::Error("max_points must be >= 1");
  if (!(runner_up_distance_m >= 0.0 && runner_up_min_ratio > 0.0 && runner_up_min_ratio <= 1.0)) {
    return core::Status::Error("need runner_up_distance_m >= 0 and runner_up_min_ratio in (0, 1]");
  }
  return core::Status::Ok();
}

PrecomputedGrids::PrecomputedGrids(const ProbabilityGrid& grid, int depth) {
  Level base;
  base.width = 1;
  base.size_x = grid.width();
  base.size_y = grid.height();
  base.values.resize(static_cast<std::size_t>(grid.width()) * grid.height());
  for (int y = 0, i = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x, ++i) {
      base.values[i] = static_cast<uint8_t>(std::lround(grid.Probability({x, y}) * 255.0));
    }
  }
  const auto floor_value =
      static_cast<uint8_t>(std::lround(grid.options().min_probability * 255.0));
  levels_.push_back(std::move(base));
  for (int h = 1; h < depth; ++h) {
    const Level& prev = levels_.back();
    const int w = prev.width;  // the new block is 2w wide: [x, x + w) and [x + w, x + 2w)
    Level next;
    next.width = 2 * w;
    next.size_x = grid.width() + next.width - 1;
    next.size_y = grid.height() + next.width - 1;
    next.values.assign(static_cast<std::size_t>(next.size_x) * next.size_y, floor_value);
    auto prev_at = [&prev, floor_value](int x, int y) -> uint8_t {  // original cell coordinates
      const int ix = x + prev.width - 1, iy = y + prev.width - 1;
      if (ix < 0 || iy < 0 || ix >= prev.size_x || iy >= prev.size_y) return floor_value;
      return prev.values[static_cast<std::size_t>(iy) * prev.size_x + ix];
    };
    for (int iy = 0; iy < next.size_y; ++iy) {
      const int y = iy - (next.width - 1);
      for (int ix = 0; ix < next.size_x; ++ix) {
        const int x = ix - (next.width - 1);
        next.values[static_cast<std::size_t>(iy) * next.size_x + ix] =
            std::max({prev_at(x, y), prev_at(x + w, y), prev_at(x, y + w), prev_at(x + w, y + w)});
      }
    }
    levels_.push_back(std::move(next));
  }
}

namespace {

struct Candidate {
  int angle = 0;  // index into the discretized scans
  int x = 0;      // cell offset
  int y = 0;
  double score = 0.0;
};

struct Search {
  const PrecomputedGrids& grids;
  const std::vector<std::vector<CellIndex>>& scans;  // per angle, cells at zero offset
  int window_cells;
  // Offsets within exclude_radius_cells of (exclude_x, exclude_y), at any
  // angle, are not solutions (the runner-up search); radius < 0: none.
  int exclude_x = 0;
  int exclude_y = 0;
  double exclude_radius_cells = -1.0;

  bool Excluded(int x, int y) const {
    const double dx = x - exclude_x, dy = y - exclude_y;
    return dx * dx + dy * dy <= exclude_radius_cells * exclude_radius_cells;
  }
  // Every offset of the node [x, x + width) x [y, y + width) is excluded.
  bool AllExcluded(int x, int y, int width) const {
    if (exclude_radius_cells < 0.0) return false;
    const int far_x = std::max(std::abs(x - exclude_x), std::abs(x + width - 1 - exclude_x));
    const int far_y = std::max(std::abs(y - exclude_y), std::abs(y + width - 1 - exclude_y));
    return static_cast<double>(far_x) * far_x + static_cast<double>(far_y) * far_y <=
           exclude_radius_cells * exclude_radius_cells;
  }

  double Score(int level, const Candidate& c) const {
    int sum = 0;  // of bytes: exact, and faster than floats
    const std::vector<CellIndex>& cells = scans[static_cast<std::size_t>(c.angle)];
    for (const CellIndex& cell : cells) sum += grids.ByteValue(level, cell.x + c.x, cell.y + c.y);
    return sum / (255.0 * static_cast<double>(cells.size()));
  }

  // Algorithm 3 of Hess et al.: depth-first, best child first, pruned by the
  // best score found so far.
  Candidate Branch(std::vector<Candidate>& candidates, int level, double min_score) const {
    std::sort(candidates.begin(), candidates.end(),
              [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
    Candidate best{0, 0, 0, min_score};
    for (const Candidate& c : candidates) {
      if (c.score <= best.score) break;
      if (AllExcluded(c.x, c.y, 1 << level)) continue;
      if (level == 0) return c;
      const int half = 1 << (level - 1);
      std::vector<Candidate> children;
      for (int dy : {0, half}) {
        for (int dx : {0, half}) {
          Candidate child{c.angle, c.x + dx, c.y + dy, 0.0};
          if (child.x > window_cells || child.y > window_cells) continue;
          child.score = Score(level - 1, child);
          children.push_back(child);
        }
      }
      const Candidate found = Branch(children, level - 1, best.score);
      if (found.score > best.score) best = found;
    }
    return best;
  }
};

}  // namespace

std::optional<BranchAndBoundMatch> BranchAndBoundSearch(
    const ProbabilityGrid& grid, const PrecomputedGrids& precomputed,
    const std::vector<core::Vector2>& points_base_m, const core::SE2& center, double min_score,
    const BranchAndBoundOptions& options) {
  if (points_base_m.empty()) return std::nullopt;
  std::vector<core::Vector2> points;
  const std::size_t stride = (points_base_m.size() + options.max_points - 1) /
                             static_cast<std::size_t>(options.max_points);
  double max_range = 0.0;
  for (std::size_t i = 0; i < points_base_m.size(); i += std::max<std::size_t>(1, stride)) {
    points.push_back(points_base_m[i]);
    max_range = std::max(max_range, points_base_m[i].norm());
  }
  const double res = grid.resolution_m();
  const double angle_step =
      max_range > res ? std::acos(1.0 - res * res / (2.0 * max_range * max_range)) : 0.1;
  const int n_angles = static_cast<int>(std::ceil(options.angular_window_rad / angle_step));
  const int window_cells = static_cast<int>(std::ceil(options.linear_window_m / res));
  std::vector<std::vector<CellIndex>> scans;
  for (int a = -n_angles; a <= n_angles; ++a) {
    const core::SE2 rotated(center.translation(), center.yaw() + a * angle_step);
    std::vector<CellIndex> cells;
    cells.reserve(points.size());
    for (const core::Vector2& p : points) cells.push_back(grid.CellOf(rotated * p));
    scans.push_back(std::move(cells));
  }
  const int top = precomputed.depth() - 1;
  const int top_width = 1 << top;
  Search search{precomputed, scans, window_cells};
  std::vector<Candidate> candidates;
  for (int a = 0; a < static_cast<int>(scans.size()); ++a) {
    for (int y = -window_cells; y <= window_cells; y += top_width) {
      for (int x = -window_cells; x <= window_cells; x += top_width) {
        Candidate c{a, x, y, 0.0};
        c.score = search.Score(top, c);
        candidates.push_back(c);
      }
    }
  }
  const Candidate best = search.Branch(candidates, top, min_score);
  if (best.score <= min_score) return std::nullopt;
  auto pose_of = [&](const Candidate& c) {
    return core::SE2(center.translation() + core::Vector2(c.x, c.y) * res,
                     center.yaw() + (c.angle - n_angles) * angle_step);
  };
  BranchAndBoundMatch match;
  match.T_grid_base = pose_of(best);
  match.score = best.score;
  if (options.runner_up_distance_m > 0.0) {
    search.exclude_x = best.x;
    search.exclude_y = best.y;
    search.exclude_radius_cells = options.runner_up_distance_m / res;
    const double floor = std::max(min_score, options.runner_up_min_ratio * best.score);
    const Candidate second = search.Branch(candidates, top, floor);
    if (second.score > floor) match.runner_up = BranchAndBoundPose{pose_of(second), second.score};
  }
  return match;
}

}  // namespace groundline::localization::lidar
