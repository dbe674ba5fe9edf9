// Private: the semantic checks shared by the Validate() methods (messages
// without a line) and the YAML readers (which look the line up from the field
// path), and the YAML formatting of the manifest and the floor map.
#ifndef GROUNDLINE_CORE_SRC_DATASET_INTERNAL_H_
#define GROUNDLINE_CORE_SRC_DATASET_INTERNAL_H_

#include <optional>
#include <string>

#include "groundline/core/dataset.h"
#include "groundline/core/floor_map.h"
#include "groundline/core/yaml_fields.h"

namespace groundline::core::internal {

// The first rule of docs/dataset.md that `manifest` breaks (except file
// existence), with the YAML path of the offending field.
std::optional<FieldProblem> CheckManifest(const DatasetManifest& manifest);
std::optional<FieldProblem> CheckFloorMap(const FloorMap& map);

// ReadFloorMap, also requiring `frame: <expected_frame>` when it is non-empty
// (the dataset's map frame).
Result<FloorMap> ReadFloorMapInFrame(const std::filesystem::path& path,
                                     const std::string& expected_frame);

// "<label>: field '<field>': expected <expected>, got '<got>'".
Status ProblemStatus(const std::string& label, const FieldProblem& problem);

// YAML text, with a comment header stating units and frames.
std::string FormatManifest(const DatasetManifest& manifest);
std::string FormatFloorMap(const FloorMap& map);

}  // namespace groundline::core::internal

#endif  // GROUNDLINE_CORE_SRC_DATASET_INTERNAL_H_
