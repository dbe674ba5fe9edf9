// The bridge from the floor-line extractor (perception/line_extractor.h) to
// the smoother's input (floor_observation.h): one camera frame's lines and
// junctions in base_link with their covariances.
//
// Kinds: the extractor knows polarity and orientation, not the marking type;
// dark lines become kJoint, bright transverse lines kStopBar, other bright
// lines kTapeSolid (association does not gate on kind; the atlas keeps the
// surveyed kind).
//
// Lines or junctions whose covariance is not symmetric positive definite
// (a degenerate fit) are dropped and counted: the smoother requires SPD
// covariances. The lone visible edge of a wide bar (ExtractedLine::
// single_bar_edge) is skipped and counted: the atlas holds a bar's centre
// line, half a bar width (~5-25 cm) away from that edge, and the bar's width
// is not known here. Pure and thread-safe.
#ifndef GROUNDLINE_LOCALIZATION_OBSERVATIONS_FROM_EXTRACTION_H_
#define GROUNDLINE_LOCALIZATION_OBSERVATIONS_FROM_EXTRACTION_H_

#include <opencv2/core.hpp>
#include <optional>

#include "groundline/localization/floor_observation.h"
#include "groundline/perception/bev_remap.h"
#include "groundline/perception/line_extractor.h"

namespace groundline::localization {

// A frame's bird's-eye view as the front end made it: the image, its seen
// cells (255), its grid and the mount it was made with.
struct BevFrame {
  cv::Mat image;
  cv::Mat seen;
  perception::BevGrid grid;
  calibration::CameraMount mount;
};

struct ConvertedObservations {
  FloorObservations observations;
  // The texture BEV of the frame the observations were made from
  // (FloorFrontEnd::TextureBev), when a camera stage hands it on for the
  // floor's texture to be tracked at the keyframe (FloorFlowTracker);
  // dropped once tracked.
  std::optional<BevFrame> bev;
  int dropped_lines = 0;      // covariance not SPD
  int dropped_junctions = 0;  // covariance not SPD
  int skipped_bar_edges = 0;  // single_bar_edge lines (not the atlas's centre line)
};

ConvertedObservations ObservationsFromExtraction(double stamp_s,
                                                 const perception::LineExtraction& extraction);

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_OBSERVATIONS_FROM_EXTRACTION_H_
