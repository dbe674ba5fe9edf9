// The floor's own texture tracked from one bird's-eye view to the next: the
// motion evidence of the camera mount's self-calibration in every frame, not
// only in frames with a marking.
//
// Concrete is textured everywhere (aggregate, stains, trowel marks). Where
// the same patch of floor lies in two BEVs made under the same (possibly
// wrong) mount, the two floor points it maps to differ by the vehicle's
// motion only when the mount is right: a wrong pitch stretches the view
// non-uniformly along x, a wrong roll shears it, a wrong height scales it and
// a wrong yaw turns the direction of travel. The tracker only measures
// where each patch went (pyramidal Lucas-Kanade on the BEV, with a
// forward-backward check); the mount is solved for elsewhere
// (calibration/mount_self_calibration.h).
//
// What is not floor texture moves otherwise: the edges of things standing on
// the floor smear with parallax, glare and the vehicle's own shadow move with
// the camera. The tracker keeps them (it cannot tell); the solver's gate and
// robust loss drop them.
//
// Stateless; thread-safe.
#ifndef GROUNDLINE_PERCEPTION_FLOOR_TEXTURE_FLOW_H_
#define GROUNDLINE_PERCEPTION_FLOOR_TEXTURE_FLOW_H_

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "groundline/core/status.h"

namespace groundline::perception {

struct FloorTextureFlowOptions {
  int max_points = 120;          // corners detected in the previous BEV
  double corner_quality = 0.01;  // of the strongest corner (goodFeaturesToTrack)
  double min_corner_distance_px = 12.0;  // spreads the points over the view
  int window_px = 21;                    // Lucas-Kanade window side (odd)
  int pyramid_levels = 3;                // 0: no pyramid
  // Forward-backward check: tracked back into the previous BEV, a point must
  // land within this of where it started.
  double max_forward_backward_px = 0.3;
  // A corner closer than this to an unseen cell is not used (the window
  // would reach outside the view, where the BEV is black).
  int margin_px = 12;

  core::Status Validate() const;
};

// One patch of floor: its cell (col, row) in the previous BEV and in the
// current one.
struct FloorTextureMatch {
  Eigen::Vector2d previous_cell = Eigen::Vector2d::Zero();
  Eigen::Vector2d current_cell = Eigen::Vector2d::Zero();
};

// Tracks texture from `previous` to `current`: two 8-bit BEVs on one grid,
// with the masks of their seen cells (255 seen). `expected_shift_cells`: where
// a patch is expected to go (col, row), e.g. the last pair's median motion;
// the search starts there. Returns the patches found in both (none when the
// images are not the same size and type, or either is empty).
std::vector<FloorTextureMatch> TrackFloorTexture(const cv::Mat& previous,
                                                 const cv::Mat& previous_seen,
                                                 const cv::Mat& current,
                                                 const cv::Mat& current_seen,
                                                 const Eigen::Vector2d& expected_shift_cells,
                                                 const FloorTextureFlowOptions& options);

}  // namespace groundline::perception

#endif  // GROUNDLINE_PERCEPTION_FLOOR_TEXTURE_FLOW_H_
