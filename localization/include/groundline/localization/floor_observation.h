// What the floor-line extractor hands to localization for one camera frame:
// ground lines and junctions measured in base_link, each with its covariance.
// The extractor (perception/) produces its own types; the tools adapt them to
// these, so localization depends only on perception's HesseLine maths.
//
// Frames and units: base_link (x forward, y left), metres and radians.
// Line covariances are of (rho_m, alpha_rad) in the description given by
// line_base (m^2, m rad, rad^2); junction covariances of (x_m, y_m) (m^2).
#ifndef GROUNDLINE_LOCALIZATION_FLOOR_OBSERVATION_H_
#define GROUNDLINE_LOCALIZATION_FLOOR_OBSERVATION_H_

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <vector>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/calibration/mount_self_calibration.h"
#include "groundline/core/floor_map.h"
#include "groundline/perception/hesse_line.h"

namespace groundline::localization {

struct LineObservation {
  perception::HesseLine line_base;
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Identity();  // symmetric positive definite
  // The camera mount's uncertainty within `covariance` (FloorFrontEnd::
  // WithMount adds it; zero otherwise): covariance - mount_covariance is
  // perception's own, what the mount's self-calibration weighs the line with
  // (the mount is what it estimates; its own uncertainty would only weaken
  // the evidence about it).
  Eigen::Matrix2d mount_covariance = Eigen::Matrix2d::Zero();
  core::MarkingKind kind = core::MarkingKind::kTapeSolid;
  // The observed extent of the marking: two points on (near) the line.
  Eigen::Vector2d endpoint_a_base_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d endpoint_b_base_m = Eigen::Vector2d::Zero();
};

// A point where markings meet or a marking turns (a corner, a T, a crossing).
struct JunctionObservation {
  Eigen::Vector2d point_base_m = Eigen::Vector2d::Zero();
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Identity();  // symmetric positive definite
};

// The floor a frame's extractor examined, in base_link: a convex polygon,
// counter-clockwise. What lies well inside it and is not reported was not
// there to be seen (or was covered); the atlas upkeep retires a landmark on
// that evidence (SmootherOptions::upkeep).
struct FloorView {
  std::vector<Eigen::Vector2d> polygon_base_m;

  // How far p lies inside the polygon: the least distance to an edge's line,
  // negative outside; -infinity for a polygon of fewer than 3 corners.
  double InsideDistance(const Eigen::Vector2d& p_base_m) const;
  // The length of the segment a-b that lies at least margin_m inside the
  // polygon (the segment clipped by each edge's inward-shifted half-plane);
  // 0 for a polygon of fewer than 3 corners.
  double LengthInside(const Eigen::Vector2d& a_base_m, const Eigen::Vector2d& b_base_m,
                      double margin_m) const;
};

// Everything extracted from one frame at stamp_s.
struct FloorObservations {
  double stamp_s = 0.0;
  std::vector<LineObservation> lines;
  std::vector<JunctionObservation> junctions;
  // The camera mount the frame's lines and junctions are under (FloorFrontEnd
  // sets it: the mount its bird's-eye view was made with, or the better
  // estimate it re-expressed them under; the self-calibration remaps the
  // lines from it). Unset: lines made elsewhere, under the commissioned
  // mount.
  std::optional<calibration::CameraMount> camera_mount;
  // The floor the frame covered (FloorFrontEnd sets it, shared by all of its
  // frames). Unset: unknown, and the frame is no evidence that a landmark is
  // gone.
  std::shared_ptr<const FloorView> view;
  // The floor's texture tracked from the frame observed before
  // (FloorFlowTracker; empty: not tracked), for the mount's self-calibration.
  calibration::FloorFlow texture_flow;
};

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_FLOOR_OBSERVATION_H_
