// `groundline localize --mode lines --relocalize`: find the start pose on the
// atlas instead of taking it from --initial-pose or the ground truth. The
// dataset is replayed from its first frame through the Relocalizer
// (localization/relocalizer.h) until one hypothesis is unambiguous; the
// localizer then starts there. Also the frame-to-observations step both
// replays share.
#ifndef GROUNDLINE_TOOLS_LOCALIZE_RELOCALIZE_H_
#define GROUNDLINE_TOOLS_LOCALIZE_RELOCALIZE_H_

#include <cstddef>
#include <filesystem>
#include <optional>

#include <nlohmann/json.hpp>

#include "groundline/core/dataset.h"
#include "groundline/core/status.h"
#include "groundline/localization/atlas.h"
#include "groundline/localization/diff_drive_odometry.h"
#include "groundline/localization/observations_from_extraction.h"
#include "groundline/localization/relocalizer.h"
#include "groundline/localization/sliding_window_smoother.h"
#include "groundline/perception/bev_remap.h"
#include "groundline/perception/line_extractor.h"

namespace groundline::tools {

// Reads the image, remaps it to the BEV and extracts its lines as
// observations stamped stamp_s; nullopt (the file named on stderr) when the
// image cannot be read.
std::optional<localization::ConvertedObservations> ObservationsOfImage(
    const std::filesystem::path& image, double stamp_s, const perception::BevRemap& remap,
    const perception::LineExtractor& extractor);

struct RelocalizedStart {
  localization::PoseEstimate pose;  // at the encoder reading that closed the frame
  double travel_m = 0.0;            // driven from the first frame to the commit
  std::size_t frames = 0;           // frames fed
  localization::RelocalizerStatus status;
};

// Replays the dataset's encoder readings and camera frames from the start
// through a Relocalizer on atlas. Fails, naming the dataset, when the drive
// ends without an unambiguous pose (with how many hypotheses were left).
core::Result<RelocalizedStart> RelocalizeOnAtlas(
    const core::Dataset& dataset, const std::filesystem::path& image_dir,
    const perception::BevRemap& remap, const perception::LineExtractor& extractor,
    const localization::DiffDriveParams& drive, const localization::OdometryNoiseParams& noise,
    const localization::Atlas& atlas, const localization::RelocalizerOptions& options);

// The summary.json block of a relocalized start: where and when it
// committed, after how much driving; with ground truth also its error
// (reference interpolated at the commit stamp).
nlohmann::ordered_json RelocalizationSummary(const RelocalizedStart& start,
                                             const core::Trajectory& ground_truth);

}  // namespace groundline::tools

#endif  // GROUNDLINE_TOOLS_LOCALIZE_RELOCALIZE_H_
