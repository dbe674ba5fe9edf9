// What `groundline localize` checks before and after a run, and how it says
// so (tools/localize_command.cc).
#ifndef GROUNDLINE_TOOLS_LOCALIZE_CHECKS_H_
#define GROUNDLINE_TOOLS_LOCALIZE_CHECKS_H_

#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "groundline/core/dataset.h"
#include "groundline/core/dataset_streams.h"
#include "groundline/core/status.h"
#include "groundline/localization/relocalizer.h"
#include "run_summary.h"

namespace groundline::tools {

// Flags a user types, refused before anything is read or written (a usage
// error: throws CLI::ValidationError, exit 2): --relocalize without --mode
// lines, --near without --relocalize, a non-finite --initial-pose or --near,
// x or y beyond 100 km, a yaw beyond one turn, a radius <= 0.
void CheckLocalizeFlags(bool relocalize, const std::string& mode,
                        const std::vector<double>& initial_pose, const std::vector<double>& near);

// Evidence rule 4 of RelocalizerOptions, said to the user: the scores the
// last time the hint was contradicted.
std::string HintNotSupported(const std::string& dataset, const Eigen::Vector2d& near_m,
                             const localization::RelocalizerStatus& s);

// summary.json's "relocalized": the committed pose (stamp_s, x_m, y_m,
// yaw_deg, sigma_xy_m), junction_sightings and, with a status, the evidence
// of the commit (RelocalizerOptions' evidence rule).
nlohmann::ordered_json RelocalizedJson(const localization::PoseEstimate& pose,
                                       const localization::RelocalizerStatus* status);

// The spans of the streams the run uses: the wheel encoders and camera
// frames from the dataset's index, the scans by one pass over their file.
// Errors: a scan line that does not parse.
core::Result<std::vector<StreamSpan>> StreamSpans(const std::filesystem::path& dir,
                                                  const core::Dataset& dataset,
                                                  const core::DatasetStreamOptions& used);

}  // namespace groundline::tools

#endif  // GROUNDLINE_TOOLS_LOCALIZE_CHECKS_H_
