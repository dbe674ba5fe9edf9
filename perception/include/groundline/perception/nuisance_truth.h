// Reads a simulator's nuisance truth (nuisance_truth.json, written by
// `groundline sim`; format in docs/perception.md) for the evaluation of
// extracted lines per nuisance class (line_evaluation.h). Evaluation only:
// the extractor never sees it.
#ifndef GROUNDLINE_PERCEPTION_NUISANCE_TRUTH_H_
#define GROUNDLINE_PERCEPTION_NUISANCE_TRUTH_H_

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/perception/line_evaluation.h"

namespace groundline::perception {

struct NuisanceTruth {
  std::vector<NuisanceLine> map_segments;  // fixed on the floor, map frame
  // Per image file: segments that move with the vehicle, base_link.
  std::map<std::string, std::vector<NuisanceLine>> frame_segments;

  // The frame's nuisances in base_link: the map segments within radius_m of
  // the vehicle, and the frame's own.
  std::vector<NuisanceLine> InView(const core::SE2& T_map_base, const std::string& file,
                                   double radius_m = 5.0) const;
};

// Errors name the file and the field.
core::Result<NuisanceTruth> ReadNuisanceTruth(const std::filesystem::path& path);

}  // namespace groundline::perception

#endif  // GROUNDLINE_PERCEPTION_NUISANCE_TRUTH_H_
