// The floor's texture tracked from one observed frame's bird's-eye view to the
// next (perception/floor_texture_flow.h), as floor points in base_link under
// each BEV's mount: FloorObservations::texture_flow, the motion evidence of
// the camera mount's self-calibration (calibration/mount_self_calibration.h)
// in every frame that sees the floor.
//
// Not thread-safe: one object per camera, fed the frames in time order by the
// thread that observes them (the localizer's, the service's camera stage).
#ifndef GROUNDLINE_LOCALIZATION_FLOOR_FLOW_TRACKER_H_
#define GROUNDLINE_LOCALIZATION_FLOOR_FLOW_TRACKER_H_

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/localization/floor_front_end.h"
#include "groundline/perception/floor_texture_flow.h"

namespace groundline::localization {

class FloorFlowTracker {
 public:
  // Valid options (asserted).
  explicit FloorFlowTracker(const perception::FloorTextureFlowOptions& options = {});

  // `bev`: the texture BEV (FloorFrontEnd::TextureBev) of the frame
  // `observations` were made from. Sets observations->texture_flow to the
  // texture tracked from the BEV given last (empty for the first, after a
  // frame older than the last, and when the grid changed), and keeps this
  // one for the next frame.
  void Track(const BevFrame& bev, FloorObservations* observations);
  // The same for the grey frame `front_end` has just observed (nothing
  // tracked, and the last BEV kept, when it is not one of its frames).
  void Track(const cv::Mat& grey, const FloorFrontEnd& front_end, FloorObservations* observations);

 private:
  perception::FloorTextureFlowOptions options_;
  // TextureBev's buffers, reused frame after frame.
  BevFrame current_{cv::Mat(), cv::Mat(), perception::BevGrid(perception::BevGridOptions{}), {}};
  bool has_previous_ = false;
  cv::Mat previous_;
  cv::Mat previous_seen_;
  std::optional<perception::BevGridOptions> previous_grid_;
  double previous_stamp_s_ = 0.0;
  calibration::CameraMount previous_mount_;
  // Where a patch went between the last two frames (cells): the next
  // search starts there (the vehicle's speed changes little frame to frame).
  Eigen::Vector2d shift_cells_ = Eigen::Vector2d::Zero();
};

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_FLOOR_FLOW_TRACKER_H_
