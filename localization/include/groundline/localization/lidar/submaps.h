// Local submaps (Cartographer-style, Hess et al. 2016, "Real-time loop
// closure in 2D LIDAR SLAM", section IV): each keyframe scan is inserted into
// the two active submaps; the older one is matched against and finishes after
// 2 * scans_per_submap scans, when the newer one (started after
// scans_per_submap) takes its place. So every finished submap holds
// 2 * scans_per_submap scans and consecutive submaps overlap by half.
// A finished submap's grid is cropped to its known cells and compressed
// (ProbabilityGrid::Compress).
//
// A submap's frame is the local frame pose of the first scan inserted into
// it, T_local_submap; its grid is written in that frame.
//
// Not thread-safe.
#ifndef GROUNDLINE_LOCALIZATION_LIDAR_SUBMAPS_H_
#define GROUNDLINE_LOCALIZATION_LIDAR_SUBMAPS_H_

#include <deque>
#include <memory>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/localization/lidar/probability_grid.h"
#include "groundline/localization/lidar/scan_points.h"

namespace groundline::localization::lidar {

struct Submap {
  Submap(int id_in, const core::SE2& T_local_submap_in, const ProbabilityGridOptions& options)
      : id(id_in),
        T_local_submap(T_local_submap_in),
        grid(options, core::Vector2(-1.6, -1.6), 64, 64) {}

  int id = 0;
  core::SE2 T_local_submap;
  ProbabilityGrid grid;  // submap frame
  int num_scans = 0;
  bool finished = false;
};

class ActiveSubmaps {
 public:
  // retain_finished: keep finished submaps in all(); false releases them
  // (their entry in all() becomes null) at the call after they finished.
  ActiveSubmaps(const ProbabilityGridOptions& grid_options, int scans_per_submap,
                bool retain_finished = true);

  // Inserts a scan taken at T_local_base (points in the base frame) into the
  // active submaps, starting a new one first when due. Returns the ids of
  // the submaps it went into; a submap that finished is in *finished.
  std::vector<int> InsertScan(const core::SE2& T_local_base, const ScanPoints& scan,
                              std::vector<std::shared_ptr<Submap>>* finished);

  // The submap to match against (the older active one); null before the first scan.
  std::shared_ptr<const Submap> matching_submap() const {
    return active_.empty() ? nullptr : active_.front();
  }
  // Every submap ever started, by id (null for a released one).
  const std::vector<std::shared_ptr<Submap>>& all() const { return all_; }

 private:
  ProbabilityGridOptions grid_options_;
  int scans_per_submap_;
  bool retain_finished_;
  std::deque<std::shared_ptr<Submap>> active_;
  std::vector<std::shared_ptr<Submap>> all_;
  std::vector<int> released_next_;
};

}  // namespace groundline::localization::lidar

#endif  // GROUNDLINE_LOCALIZATION_LIDAR_SUBMAPS_H_
