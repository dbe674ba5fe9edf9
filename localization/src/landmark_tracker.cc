#include "groundline/localization/landmark_tracker.h"
#include "groundline/core/covariance.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <limits>

namespace groundline::localization {
void FuseGaussian2(const Eigen::Vector2d& innovation, const Eigen::Matrix2d& R, Eigen::Vector2d* x,
                   Eigen::Matrix2d* P) {
  const Eigen::Matrix2d K = *P * (*P + R).inverse();
  *x += K * innovation;
  *P = (Eigen::Matrix2d::Identity() - K) * *P;
  *P = 0.5 * (*P + P->transpose());
}

AtlasLine LineInMap(const LineObservation& observation, const core::SE2& T_map_base,
                    const core::Matrix3& pose_covariance) {
  perception::Matrix23 J_T;
  Eigen::Matrix2d J_l;
  AtlasLine out;
  out.line_map = perception::TransformLine(T_map_base, observation.line_base, &J_T, &J_l);
  out.covariance =
      J_l * observation.covariance * J_l.transpose() + J_T * pose_covariance * J_T.transpose();
  out.kind = observation.kind;
  out.endpoint_a_m = T_map_base * observation.endpoint_a_base_m;
  out.endpoint_b_m = T_map_base * observation.endpoint_b_base_m;
  return out;
}

void ExtendLineExtent(const Eigen::Vector2d& point_m, AtlasLine* line) {
  const Eigen::Vector2d d = line->line_map.Direction();
  const double s = d.dot(point_m);
  const double s_a = d.dot(line->endpoint_a_m);
  const double s_b = d.dot(line->endpoint_b_m);
  Eigen::Vector2d* low = s_a <= s_b ? &line->endpoint_a_m : &line->endpoint_b_m;
  Eigen::Vector2d* high = s_a <= s_b ? &line->endpoint_b_m : &line->endpoint_a_m;
  // Keep the ends on the line: move them along its direction only.
  if (s < std::min(s_a, s_b)) *low += (s - std::min(s_a, s_b)) * d;
  if (s > std::max(s_a, s_b)) *high += (s - std::max(s_a, s_b)) * d;
}

void FuseLineSighting(const AtlasLine& seen, AtlasLine* estimate) {
  Eigen::Vector2d x(estimate->line_map.rho_m, estimate->line_map.alpha_rad);
  FuseGaussian2(
      perception::LineDifference(seen.line_map, estimate->line_map),
      perception::CovarianceInDescriptionOf(seen.line_map, estimate->line_map, seen.covariance), &x,
      &estimate->covariance);
  estimate->line_map = perception::NormalizeLine(x(0), x(1), &estimate->covariance);
  ExtendLineExtent(seen.endpoint_a_m, estimate);
  ExtendLineExtent(seen.endpoint_b_m, estimate);
}

AtlasJunction JunctionInMap(const JunctionObservation& observation, const core::SE2& T_map_base,
                            const core::Matrix3& pose_covariance) {
  Eigen::Matrix<double, 2, 3> J_T;
  Eigen::Matrix2d J_p;
  AtlasJunction out;
  out.point_m = T_map_base.Act(observation.point_base_m, &J_T, &J_p);
  out.covariance =
      J_p * observation.covariance * J_p.transpose() + J_T * pose_covariance * J_T.transpose();
  return out;
}

void FuseJunctionSighting(const AtlasJunction& seen, AtlasJunction* estimate) {
  FuseGaussian2(seen.point_m - estimate->point_m, seen.covariance, &estimate->point_m,
                &estimate->covariance);
}

LandmarkTracker::Confirmed LandmarkTracker::Update(
    long keyframe_index, const core::SE2& T_map_base, const core::Matrix3& pose_covariance,
    const std::vector<const LineObservation*>& lines,
    const std::vector<const JunctionObservation*>& junctions) {
  Confirmed confirmed;
  for (size_t i = 0; i < lines.size(); ++i) {
    const AtlasLine seen = LineInMap(*lines[i], T_map_base, pose_covariance);
    int best = -1;
    double best_d2 = options_.gate_chi2;
    for (size_t t = 0; t < lines_.size(); ++t) {
      const AtlasLine& track = lines_[t].estimate;
      // nu is in the track's description; so must the seen line's covariance be.
      const Eigen::Vector2d nu = perception::LineDifference(seen.line_map, track.line_map);
      const double d2 = core::SquaredMahalanobis<2>(
          nu,
          perception::CovarianceInDescriptionOf(seen.line_map, track.line_map, seen.covariance) +
              track.covariance);
      if (d2 <= best_d2 && lines_[t].last_keyframe < keyframe_index) {
        best_d2 = d2;
        best = static_cast<int>(t);
      }
    }
    if (best < 0) {
      lines_.push_back({seen, 1, keyframe_index});
      continue;
    }
    LineTrack& track = lines_[best];
    FuseLineSighting(seen, &track.estimate);
    track.last_keyframe = keyframe_index;
    if (++track.sightings == options_.min_keyframes) {
      confirmed.lines.push_back({track.estimate, static_cast<int>(i)});
    }
  }
  for (size_t i = 0; i < junctions.size(); ++i) {
    const AtlasJunction seen = JunctionInMap(*junctions[i], T_map_base, pose_covariance);
    int best = -1;
    double best_d2 = options_.gate_chi2;
    for (size_t t = 0; t < junctions_.size(); ++t) {
      const AtlasJunction& track = junctions_[t].estimate;
      const double d2 = core::SquaredMahalanobis<2>(seen.point_m - track.point_m,
                                                    seen.covariance + track.covariance);
      if (d2 <= best_d2 && junctions_[t].last_keyframe < keyframe_index) {
        best_d2 = d2;
        best = static_cast<int>(t);
      }
    }
    if (best < 0) {
      junctions_.push_back({seen, 1, keyframe_index});
      continue;
    }
    JunctionTrack& track = junctions_[best];
    FuseJunctionSighting(seen, &track.estimate);
    track.last_keyframe = keyframe_index;
    if (++track.sightings == options_.min_keyframes) {
      confirmed.junctions.push_back({track.estimate, static_cast<int>(i)});
    }
  }
  const auto stale = [&](const auto& track) {
    return track.sightings >= options_.min_keyframes ||
           keyframe_index - track.last_keyframe > options_.max_gap_keyframes;
  };
  lines_.erase(std::remove_if(lines_.begin(), lines_.end(), stale), lines_.end());
  junctions_.erase(std::remove_if(junctions_.begin(), junctions_.end(), stale), junctions_.end());
  return confirmed;
}

}  // namespace groundline::localization
