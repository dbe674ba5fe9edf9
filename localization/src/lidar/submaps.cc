#include "groundline/localization/lidar/submaps.h"

#include <cassert>

namespace groundline::localization::lidar {

ActiveSubmaps::ActiveSubmaps(const ProbabilityGridOptions& grid_options, int scans_per_submap,
                             bool retain_finished)
    : grid_options_(grid_options),
      scans_per_submap_(scans_per_submap),
      retain_finished_(retain_finished) {
  assert(scans_per_submap >= 1);
}

std::vector<int> ActiveSubmaps::InsertScan(const core::SE2& T_local_base, const ScanPoints& scan,
                                           std::vector<std::shared_ptr<Submap>>* finished) {
  // Submaps that finished in the previous call: the caller has seen them.
  for (int id : released_next_) all_[static_cast<std::size_t>(id)].reset();
  released_next_.clear();
  if (active_.empty() || active_.back()->num_scans >= scans_per_submap_) {
    auto submap =
        std::make_shared<Submap>(static_cast<int>(all_.size()), T_local_base, grid_options_);
    active_.push_back(submap);
    all_.push_back(submap);
  }
  std::vector<int> ids;
  for (const std::shared_ptr<Submap>& submap : active_) {
    const core::SE2 T_submap_base = submap->T_local_submap.Between(T_local_base);
    std::vector<core::Vector2> hits, misses;
    hits.reserve(scan.points.size());
    for (const ScanPoint& p : scan.points) hits.push_back(T_submap_base * p.point_m);
    for (const core::Vector2& m : scan.misses_m) misses.push_back(T_submap_base * m);
    submap->grid.InsertScan(T_submap_base * scan.sensor_origin_m, hits, misses);
    ++submap->num_scans;
    ids.push_back(submap->id);
  }
  while (active_.size() > 1 && active_.front()->num_scans >= 2 * scans_per_submap_) {
    active_.front()->finished = true;
    active_.front()->grid.CropToKnown();
    active_.front()->grid.Compress();
    if (finished != nullptr) finished->push_back(active_.front());
    if (!retain_finished_) released_next_.push_back(active_.front()->id);
    active_.pop_front();
  }
  return ids;
}

}  // namespace groundline::localization::lidar
