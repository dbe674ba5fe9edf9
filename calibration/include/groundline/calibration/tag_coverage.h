// What a live floor calibration (`groundline calibrate floor --live`) still
// lacks: which tags of the layout have been seen in enough frames.
//
// A frame is kept when it shows a layout tag seen in fewer than
// min_frames_per_tag kept frames so far; a frame with no layout tag, or
// only tags that already have enough frames, adds nothing. Complete() when
// every tag of the layout is in at least min_frames_per_tag kept frames.
// Ids not in the layout are reported (a wrong tag on the floor, or the wrong
// layout file) but never counted.
//
// Pure: no I/O. Not thread-safe.
#ifndef GROUNDLINE_CALIBRATION_TAG_COVERAGE_H_
#define GROUNDLINE_CALIBRATION_TAG_COVERAGE_H_

#include <map>
#include <set>
#include <string>
#include <vector>

#include "groundline/calibration/tag_layout.h"

namespace groundline::calibration {

class TagCoverage {
 public:
  // layout must be valid and min_frames_per_tag >= 1 (asserted).
  TagCoverage(const TagLayout& layout, int min_frames_per_tag);

  struct Verdict {
    bool kept = false;
    std::vector<int> layout_ids;   // layout tags in the frame, sorted
    std::vector<int> unknown_ids;  // tags not in the layout, sorted
    std::string reason;            // what it added, or why it adds nothing
  };
  // Judges a frame from the ids of the tags detected in it; keeps it when it
  // adds something.
  Verdict Consider(const std::vector<int>& detected_ids);

  int frames() const { return frames_; }
  bool Complete() const { return Missing().empty(); }
  // "not yet seen: tags 4 7 9" and "need more frames of: tag 2 (1 of 3), ...";
  // empty when Complete().
  std::vector<std::string> Missing() const;
  // "3 frames; tags seen 10 of 12", with "; coverage complete" appended
  // when Complete().
  std::string StatusLine() const;

 private:
  std::map<int, int> frames_per_tag_;  // every layout id, 0 when unseen
  int min_frames_per_tag_;
  int frames_ = 0;
};

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_TAG_COVERAGE_H_
