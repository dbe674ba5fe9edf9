// A double for a JSON output: JSON has no NaN or infinity, so those are null.
#ifndef GROUNDLINE_TOOLS_JSON_NUMBER_H_
#define GROUNDLINE_TOOLS_JSON_NUMBER_H_

#include <cmath>

#include <nlohmann/json.hpp>

namespace groundline::tools {

inline nlohmann::ordered_json FiniteOrNull(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json();
}

}  // namespace groundline::tools

#endif  // GROUNDLINE_TOOLS_JSON_NUMBER_H_
