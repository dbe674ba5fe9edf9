// Decides when the motion since the last keyframe is large enough for a new
// one: a keyframe is due once base_link has moved at least min_translation_m
// (straight-line distance from the keyframe, not path length) or turned at
// least min_rotation_rad (wrapped yaw difference) since the keyframe.
//
// Stateless apart from its options; thread-safe.
#ifndef GROUNDLINE_LOCALIZATION_KEYFRAME_SELECTOR_H_
#define GROUNDLINE_LOCALIZATION_KEYFRAME_SELECTOR_H_

#include <numbers>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"

namespace groundline::localization {

class KeyframeSelector {
 public:
  struct Options {
    double min_translation_m = 0.20;
    double min_rotation_rad = 5.0 * std::numbers::pi / 180.0;

    // Ok if min_translation_m is finite and > 0 and min_rotation_rad is in
    // (0, pi]; otherwise names the field and the value.
    core::Status Validate() const;
  };

  // The options must be valid (asserted).
  explicit KeyframeSelector(const Options& options);

  // T_keyframe_base: the current pose in the frame of the last keyframe
  // (OdometryIntegrator::SinceKeyframe().T_start_end).
  bool IsKeyframeDue(const core::SE2& T_keyframe_base) const;

  const Options& options() const { return options_; }

 private:
  Options options_;
};

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_KEYFRAME_SELECTOR_H_
