#include "groundline/localization/floor_flow_tracker.h"

#include <algorithm>
#include <cassert>
#include <vector>

namespace groundline::localization {

FloorFlowTracker::FloorFlowTracker(const perception::FloorTextureFlowOptions& options)
    : options_(options) {
  assert(options.Validate().ok());
}

namespace {

bool SameGrid(const perception::BevGridOptions& a, const perception::BevGridOptions& b) {
  return a.x_min_m == b.x_min_m && a.x_max_m == b.x_max_m && a.y_min_m == b.y_min_m &&
         a.y_max_m == b.y_max_m && a.cell_m == b.cell_m;
}

}  // namespace

void FloorFlowTracker::Track(const cv::Mat& grey, const FloorFrontEnd& front_end,
                             FloorObservations* observations) {
  observations->texture_flow = {};
  if (!front_end.TextureBev(grey, &current_).ok()) return;
  Track(current_, observations);
}

void FloorFlowTracker::Track(const BevFrame& frame, FloorObservations* observations) {
  observations->texture_flow = {};
  const cv::Mat& bev = frame.image;
  const perception::BevGrid& grid = frame.grid;
  const cv::Mat& seen = frame.seen;
  if (has_previous_ && observations->stamp_s > previous_stamp_s_ && previous_grid_ &&
      SameGrid(*previous_grid_, grid.options()) && previous_.size() == bev.size() &&
      previous_.type() == bev.type()) {
    const std::vector<perception::FloorTextureMatch> matches = perception::TrackFloorTexture(
        previous_, previous_seen_, bev, seen, shift_cells_, options_);
    calibration::FloorFlow& flow = observations->texture_flow;
    flow.previous_stamp_s = previous_stamp_s_;
    flow.previous_mount = previous_mount_;
    flow.current_mount = frame.mount;
    flow.points.reserve(matches.size());
    std::vector<double> dc, dr;
    for (const perception::FloorTextureMatch& m : matches) {
      flow.points.emplace_back(grid.FloorPointOfCell(m.previous_cell),
                               grid.FloorPointOfCell(m.current_cell));
      dc.push_back(m.current_cell.x() - m.previous_cell.x());
      dr.push_back(m.current_cell.y() - m.previous_cell.y());
    }
    if (!dc.empty()) {
      const auto mid = dc.size() / 2;
      std::nth_element(dc.begin(), dc.begin() + mid, dc.end());
      std::nth_element(dr.begin(), dr.begin() + mid, dr.end());
      shift_cells_ = {dc[mid], dr[mid]};
    }
  }
  bev.copyTo(previous_);
  seen.copyTo(previous_seen_);
  previous_stamp_s_ = observations->stamp_s;
  previous_mount_ = frame.mount;
  previous_grid_ = grid.options();
  has_previous_ = true;
}

}  // namespace groundline::localization
