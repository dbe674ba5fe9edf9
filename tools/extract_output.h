// Output of `groundline extract`: the JSON of one frame's lines, the summary,
// and the BEV / overlay images (tools/extract_command.cc).
#ifndef GROUNDLINE_TOOLS_EXTRACT_OUTPUT_H_
#define GROUNDLINE_TOOLS_EXTRACT_OUTPUT_H_

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <span>
#include <string>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/perception/bev_remap.h"
#include "groundline/perception/ground_truth_lines.h"
#include "groundline/perception/line_evaluation.h"
#include "groundline/perception/line_extractor.h"

namespace groundline::tools {

// {"image", "ms", "lines": [{rho_m, alpha_rad, cov, kind, start_m, end_m,
// length_m, bar, edge, samples, rms_residual_m,
// noise_sigma_px}], "junctions": [{point_m, cov,
// lines, shape}]}.
nlohmann::ordered_json FrameToJson(const std::string& image, double ms,
                                   const perception::LineExtraction& extraction);

// The matched true line of an extracted one: {marking_id, kind, edge,
// evaluated, error: [d rho m, d alpha rad] (extracted - true), nees}.
nlohmann::ordered_json TruthToJson(const perception::ExtractedLine& line,
                                   const perception::TrueLine& truth);

// A missed (evaluated, unmatched) true line: {marking_id, kind, edge, rho_m,
// alpha_rad, start_m, end_m, evaluated_length_m} (base_link).
nlohmann::ordered_json MissedTruthToJson(const perception::TrueLine& truth);

// The mount the extraction used: {source, height_m, pitch_deg, roll_deg,
// yaw_deg, forward_m, lateral_m}.
nlohmann::ordered_json MountToJson(const calibration::CameraMount& mount,
                                   const std::string& source);

// The summary's rate fields of one breakdown.
nlohmann::ordered_json ErrorSummaryToJson(const perception::LineErrorSummary& summary);

// Per nuisance class (LineEvaluation::by_nuisance): {class: {false_lines,
// false_share (of every detection of the frames), truths_touched,
// tpr_touched}}; "none" holds the false lines along no nuisance.
nlohmann::ordered_json NuisanceSummaryToJson(const perception::LineEvaluation& evaluation);
// The same as a table on stdout.
void PrintNuisanceTable(const perception::LineEvaluation& evaluation);

// The overlay's colours (BGR), explained in its legend and docs/perception.md.
inline const cv::Scalar kBrightColour(0, 220, 0);        // green
inline const cv::Scalar kDarkColour(255, 0, 255);        // magenta
inline const cv::Scalar kSingleEdgeColour(255, 255, 0);  // cyan
inline const cv::Scalar kJunctionColour(0, 0, 255);      // red
inline const cv::Scalar kTruthColour(255, 120, 0);       // blue

// The BEV in colour, upsampled 3x, with the extracted lines (bright: green,
// dark: magenta, the one visible edge of a wide bar: cyan; bar centre lines
// thicker), junctions (red circles) and, if given, the true lines (thin
// blue); a legend of these below it (WithLegend).
cv::Mat DrawOverlay(const cv::Mat& bev, const perception::BevGrid& grid,
                    const perception::LineExtraction& extraction,
                    std::span<const perception::TrueLine> truths);

// `overlay` with a white legend strip below it, one row per colour (the
// ground-truth row only when with_truth).
cv::Mat WithLegend(const cv::Mat& overlay, bool with_truth);

}  // namespace groundline::tools

#endif  // GROUNDLINE_TOOLS_EXTRACT_OUTPUT_H_
