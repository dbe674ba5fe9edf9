#include "groundline/localization/keyframe_selector.h"

#include <cassert>
#include <cmath>
#include <sstream>

namespace groundline::localization {

core::Status KeyframeSelector::Options::Validate() const {
  std::ostringstream out;
  if (!(std::isfinite(min_translation_m) && min_translation_m > 0.0)) {
    out << "KeyframeSelector::Options.min_translation_m: expected a finite value > 0 [m], got "
        << min_translation_m;
    return core::Status::Error(out.str());
  }
  if (!(min_rotation_rad > 0.0 && min_rotation_rad <= std::numbers::pi)) {
    out << "KeyframeSelector::Options.min_rotation_rad: expected a value in (0, pi] [rad], got "
        << min_rotation_rad;
    return core::Status::Error(out.str());
  }
  return core::Status::Ok();
}

KeyframeSelector::KeyframeSelector(const Options& options) : options_(options) {
  assert(options_.Validate().ok());
}

bool KeyframeSelector::IsKeyframeDue(const core::SE2& T_keyframe_base) const {
  return T_keyframe_base.translation().norm() >= options_.min_translation_m ||
         std::abs(core::WrapAngle(T_keyframe_base.yaw())) >= options_.min_rotation_rad;
}

}  // namespace groundline::localization
