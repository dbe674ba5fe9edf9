#include "groundline/calibration/tag_coverage.h"

#include <algorithm>
#include <cassert>

namespace groundline::calibration {
namespace {

std::string IdList(const std::vector<int>& ids) {
  std::string s;
  for (int id : ids) s += " " + std::to_string(id);
  return s;
}

}  // namespace

TagCoverage::TagCoverage(const TagLayout& layout, int min_frames_per_tag)
    : min_frames_per_tag_(min_frames_per_tag) {
  assert(layout.Validate().ok() && min_frames_per_tag >= 1);
  for (const SurveyedTag& t : layout.tags) frames_per_tag_[t.id] = 0;
}

TagCoverage::Verdict TagCoverage::Consider(const std::vector<int>& detected_ids) {
  Verdict v;
  std::vector<int> needed;
  for (int id : std::set<int>(detected_ids.begin(), detected_ids.end())) {
    const auto it = frames_per_tag_.find(id);
    if (it == frames_per_tag_.end()) {
      v.unknown_ids.push_back(id);
      continue;
    }
    v.layout_ids.push_back(id);
    if (it->second < min_frames_per_tag_) needed.push_back(id);
  }
  if (v.layout_ids.empty()) {
    v.reason = "no tag of the layout in view" +
               (v.unknown_ids.empty() ? std::string()
                                      : " (tags" + IdList(v.unknown_ids) + " are not in it)");
    return v;
  }
  if (needed.empty()) {
    v.reason = "tags" + IdList(v.layout_ids) + " already have " +
               std::to_string(min_frames_per_tag_) + " frames: point the camera at other tags";
    return v;
  }
  for (int id : v.layout_ids) ++frames_per_tag_[id];
  ++frames_;
  v.kept = true;
  v.reason = "kept: tags" + IdList(v.layout_ids);
  return v;
}

std::vector<std::string> TagCoverage::Missing() const {
  std::vector<int> unseen;
  std::string few;
  for (const auto& [id, n] : frames_per_tag_) {
    if (n == 0) {
      unseen.push_back(id);
    } else if (n < min_frames_per_tag_) {
      few += (few.empty() ? " tag " : ", tag ") + std::to_string(id) + " (" + std::to_string(n) +
             " of " + std::to_string(min_frames_per_tag_) + ")";
    }
  }
  std::vector<std::string> missing;
  if (!unseen.empty()) {
    missing.push_back("not yet seen: tags" + IdList(unseen) +
                      ": point the camera at them (or move the vehicle)");
  }
  if (!few.empty()) missing.push_back("need more frames of:" + few);
  return missing;
}

std::string TagCoverage::StatusLine() const {
  int seen = 0;
  for (const auto& [id, n] : frames_per_tag_) seen += n > 0 ? 1 : 0;
  return std::to_string(frames_) + " frames; tags seen " + std::to_string(seen) + " of " +
         std::to_string(frames_per_tag_.size()) + (Complete() ? "; coverage complete" : "");
}

}  // namespace groundline::calibration
