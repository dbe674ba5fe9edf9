#include "groundline/localization/lidar/probability_grid.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

namespace groundline::localization::lidar {
namespace {

float Logit(double p) { return static_cast<float>(std::log(p / (1.0 - p))); }

float ProbabilityFromLogOdds(float l) { return 1.0f / (1.0f + std::exp(-l)); }

constexpr float kUnknown = std::numeric_limits<float>::quiet_NaN();

}  // namespace

core::Status ProbabilityGridOptions::Validate() const {
  if (!(resolution_m > 0.0)) return core::Status::Error("resolution_m must be > 0");
  for (double p : {hit_probability, miss_probability, min_probability, max_probability}) {
    if (!(p > 0.0 && p < 1.0)) return core::Status::Error("probabilities must be in (0, 1)");
  }
  if (!(hit_probability > 0.5)) return core::Status::Error("hit_probability must be > 0.5");
  if (!(miss_probability < 0.5)) return core::Status::Error("miss_probability must be < 0.5");
  if (!(min_probability < 0.5 && max_probability > 0.5)) {
    return core::Status::Error("need min_probability < 0.5 < max_probability");
  }
  return core::Status::Ok();
}

ProbabilityGrid::ProbabilityGrid(const ProbabilityGridOptions& options,
                                 const core::Vector2& origin_m, int width, int height)
    : options_(options), origin_m_(origin_m), width_(width), height_(height) {
  assert(options.Validate().ok());
  assert(width > 0 && height > 0);
  hit_log_odds_ = Logit(options.hit_probability);
  miss_log_odds_ = Logit(options.miss_probability);
  min_log_odds_ = Logit(options.min_probability);
  max_log_odds_ = Logit(options.max_probability);
  const auto n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  log_odds_.assign(n, kUnknown);
  probability_.assign(n, static_cast<float>(options.min_probability));
  last_scan_.assign(n, 0);
}

CellIndex ProbabilityGrid::CellOf(const core::Vector2& point_m) const {
  const core::Vector2 c = (point_m - origin_m_) / options_.resolution_m;
  return {static_cast<int>(std::floor(c.x())), static_cast<int>(std::floor(c.y()))};
}

bool ProbabilityGrid::IsKnown(const CellIndex& cell) const {
  if (!Contains(cell)) return false;
  return compressed_ ? compressed_probability_[Index(cell)] != 0
                     : !std::isnan(log_odds_[Index(cell)]);
}

bool ProbabilityGrid::IsFreeAround(const CellIndex& cell, double free_probability) const {
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const CellIndex n{cell.x + dx, cell.y + dy};
      if (!IsKnown(n) || Probability(n) >= free_probability) return false;
    }
  }
  return true;
}

void ProbabilityGrid::Compress() {
  if (compressed_) return;
  compressed_probability_.resize(probability_.size());
  for (std::size_t i = 0; i < probability_.size(); ++i) {
    compressed_probability_[i] =
        std::isnan(log_odds_[i])
            ? uint16_t{0}
            : static_cast<uint16_t>(
                  1 + std::lround(std::clamp(probability_[i], 0.0f, 1.0f) * 65534.0f));
  }
  std::vector<float>().swap(log_odds_);
  std::vector<float>().swap(probability_);
  std::vector<uint32_t>().swap(last_scan_);
  compressed_ = true;
}

void ProbabilityGrid::Update(int index, float delta_log_odds) {
  const auto i = static_cast<std::size_t>(index);
  if (last_scan_[i] == scan_count_) return;
  last_scan_[i] = scan_count_;
  float& l = log_odds_[i];
  if (std::isnan(l)) {
    l = 0.0f;
    ++known_cells_;
  }
  l = std::clamp(l + delta_log_odds, min_log_odds_, max_log_odds_);
  probability_[i] = ProbabilityFromLogOdds(l);
}

void ProbabilityGrid::GrowToContain(const core::Vector2& min_m, const core::Vector2& max_m) {
  const CellIndex lo = CellOf(min_m);
  const CellIndex hi = CellOf(max_m);
  if (Contains(lo) && Contains(hi)) return;
  int add_left = 0, add_bottom = 0, new_width = width_, new_height = height_;
  while (lo.x + add_left < 0) add_left += new_width / 2, new_width += new_width / 2;
  while (lo.y + add_bottom < 0) add_bottom += new_height / 2, new_height += new_height / 2;
  while (hi.x + add_left >= new_width) new_width += new_width / 2;
  while (hi.y + add_bottom >= new_height) new_height += new_height / 2;
  const auto n = static_cast<std::size_t>(new_width) * static_cast<std::size_t>(new_height);
  std::vector<float> log_odds(n, kUnknown);
  std::vector<float> probability(n, static_cast<float>(options_.min_probability));
  std::vector<uint32_t> last_scan(n, 0);
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      const std::size_t from = Index({x, y});
      const std::size_t to = static_cast<std::size_t>(y + add_bottom) * new_width + x + add_left;
      log_odds[to] = log_odds_[from];
      probability[to] = probability_[from];
      last_scan[to] = last_scan_[from];
    }
  }
  log_odds_.swap(log_odds);
  probability_.swap(probability);
  last_scan_.swap(last_scan);
  origin_m_ -= core::Vector2(add_left, add_bottom) * options_.resolution_m;
  width_ = new_width;
  height_ = new_height;
}

void ProbabilityGrid::InsertScan(const core::Vector2& sensor_origin_m,
                                 const std::vector<core::Vector2>& hits_m,
                                 const std::vector<core::Vector2>& misses_only_m) {
  assert(!compressed_);
  core::Vector2 lo = sensor_origin_m, hi = sensor_origin_m;
  for (const auto* points : {&hits_m, &misses_only_m}) {
    for (const core::Vector2& p : *points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  const core::Vector2 margin = core::Vector2::Constant(2.0 * options_.resolution_m);
  GrowToContain(lo - margin, hi + margin);
  ++scan_count_;
  for (const core::Vector2& p : hits_m) Update(static_cast<int>(Index(CellOf(p))), hit_log_odds_);
  const CellIndex start = CellOf(sensor_origin_m);
  auto trace = [&](const core::Vector2& end_m, bool stop_before_end) {
    const CellIndex end = CellOf(end_m);
    ForEachCellOnLine(start, end, [&](const CellIndex& c) {
      if (stop_before_end && c.x == end.x && c.y == end.y) return false;
      Update(static_cast<int>(Index(c)), miss_log_odds_);
      return true;
    });
  };
  for (const core::Vector2& p : hits_m) trace(p, true);
  for (const core::Vector2& p : misses_only_m) trace(p, false);
}

void ProbabilityGrid::CropToKnown() {
  assert(!compressed_);
  int min_x = width_, min_y = height_, max_x = -1, max_y = -1;
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      if (std::isnan(log_odds_[Index({x, y})])) continue;
      min_x = std::min(min_x, x), max_x = std::max(max_x, x);
      min_y = std::min(min_y, y), max_y = std::max(max_y, y);
    }
  }
  if (max_x < 0) return;
  min_x = std::max(0, min_x - 1), min_y = std::max(0, min_y - 1);
  max_x = std::min(width_ - 1, max_x + 1), max_y = std::min(height_ - 1, max_y + 1);
  const int new_width = max_x - min_x + 1, new_height = max_y - min_y + 1;
  const auto n = static_cast<std::size_t>(new_width) * static_cast<std::size_t>(new_height);
  std::vector<float> log_odds(n), probability(n);
  std::vector<uint32_t> last_scan(n);
  for (int y = 0; y < new_height; ++y) {
    for (int x = 0; x < new_width; ++x) {
      const std::size_t from = Index({x + min_x, y + min_y});
      const std::size_t to = static_cast<std::size_t>(y) * new_width + x;
      log_odds[to] = log_odds_[from];
      probability[to] = probability_[from];
      last_scan[to] = last_scan_[from];
    }
  }
  log_odds_.swap(log_odds);
  probability_.swap(probability);
  last_scan_.swap(last_scan);
  origin_m_ += core::Vector2(min_x, min_y) * options_.resolution_m;
  width_ = new_width;
  height_ = new_height;
}

}  // namespace groundline::localization::lidar
