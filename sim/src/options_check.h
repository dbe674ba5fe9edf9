// Validation helpers for the Options structs of the sim module.
#ifndef GROUNDLINE_SIM_SRC_OPTIONS_CHECK_H_
#define GROUNDLINE_SIM_SRC_OPTIONS_CHECK_H_

#include <initializer_list>
#include <sstream>

#include "groundline/core/status.h"

namespace groundline::sim::internal {

// Ok if lo <= value <= hi (NaN fails), else
// "<owner>.<field>: expected a value in [lo, hi], got <value>".
inline core::Status CheckRange(const char* owner, const char* field, double value, double lo,
                               double hi) {
  if (value >= lo && value <= hi) return core::Status::Ok();
  std::ostringstream message;
  message << owner << "." << field << ": expected a value in [" << lo << ", " << hi << "], got "
          << value;
  return core::Status::Error(message.str());
}

// The first error among the statuses, or ok.
inline core::Status FirstError(std::initializer_list<core::Status> statuses) {
  for (const core::Status& status : statuses) {
    if (!status.ok()) return status;
  }
  return core::Status::Ok();
}

}  // namespace groundline::sim::internal

#endif  // GROUNDLINE_SIM_SRC_OPTIONS_CHECK_H_
