#include "groundline/localization/floor_association.h"
#include "groundline/core/covariance.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cassert>
#include <limits>

namespace groundline::localization {
namespace {

// Nearest-neighbour selection with ambiguity rejection over d2 per landmark.
// same(i, j): landmarks i and j are one physical landmark (duplicates in the
// atlas, e.g. a marking drawn twice); they do not make a match ambiguous.
template <typename Distance, typename Same>
Match Select(int observation, int num_landmarks, const Distance& distance, const Same& same,
             const AssociationOptions& options) {
  Match match;
  match.observation = observation;
  double best = std::numeric_limits<double>::infinity();
  double second = best;
  int best_index = -1;
  int second_index = -1;
  for (int j = 0; j < num_landmarks; ++j) {
    const double d2 = distance(j);
    match.nearest_mahalanobis2 = std::min(match.nearest_mahalanobis2, d2);
    if (!(d2 <= options.gate_chi2)) continue;
    if (d2 < best) {
      second = best;
      second_index = best_index;
      best = d2;
      best_index = j;
    } else if (d2 < second) {
      second = d2;
      second_index = j;
    }
  }
  if (second_index >= 0 && same(best_index, second_index)) second = best + 1e9;
  if (best_index < 0) return match;
  match.mahalanobis2 = best;
  if (second - best < options.ambiguity_margin_chi2) {
    match.ambiguous = true;
    return match;
  }
  match.landmark = best_index;
  return match;
}

}  // namespace

bool KindsCompatible(core::MarkingKind observed, core::MarkingKind landmark) {
  if (core::IsFaceKind(observed)) return observed == landmark;
  return !core::IsFaceKind(landmark);
}

core::Status AssociationOptions::Validate() const {
  if (!(gate_chi2 > 0.0)) return core::Status::Error("association gate_chi2 must be > 0");
  if (!(ambiguity_margin_chi2 >= 0.0)) {
    return core::Status::Error("association ambiguity_margin_chi2 must be >= 0");
  }
  if (!(extent_margin_m >= 0.0)) {
    return core::Status::Error("association extent_margin_m must be >= 0");
  }
  return core::Status::Ok();
}

double LineMahalanobis2(const LineObservation& observation, const AtlasLine& landmark,
                        const core::SE2& T_map_base, const core::Matrix3& pose_covariance) {
  perception::Matrix23 J_T;
  Eigen::Matrix2d J_l;
  const perception::HesseLine predicted =
      perception::InverseTransformLine(T_map_base, landmark.line_map, &J_T, &J_l);
  Eigen::Matrix2d J_d;
  const Eigen::Vector2d innovation =
      perception::LineDifference(predicted, observation.line_base, &J_d);
  const Eigen::Matrix<double, 2, 3> A = J_d * J_T;
  const Eigen::Matrix2d B = J_d * J_l;
  const Eigen::Matrix2d S = observation.covariance + A * pose_covariance * A.transpose() +
                            B * landmark.covariance * B.transpose();
  return core::SquaredMahalanobis<2>(innovation, S);
}

double JunctionMahalanobis2(const JunctionObservation& observation, const AtlasJunction& landmark,
                            const core::SE2& T_map_base, const core::Matrix3& pose_covariance) {
  const Eigen::Matrix2d R_T = T_map_base.Rotation().transpose();
  const Eigen::Vector2d p = R_T * (landmark.point_m - T_map_base.translation());
  Eigen::Matrix<double, 2, 3> J_T;
  J_T << -1.0, 0.0, p.y(), 0.0, -1.0, -p.x();
  const Eigen::Matrix2d S = observation.covariance + J_T * pose_covariance * J_T.transpose() +
                            R_T * landmark.covariance * R_T.transpose();
  return core::SquaredMahalanobis<2>(p - observation.point_base_m, S);
}

bool ExtentsOverlap(const LineObservation& observation, const AtlasLine& landmark,
                    const core::SE2& T_map_base, double margin_m) {
  const Eigen::Vector2d direction = landmark.line_map.Direction();
  const double s_a = direction.dot(landmark.endpoint_a_m);
  const double s_b = direction.dot(landmark.endpoint_b_m);
  const double o_a = direction.dot(T_map_base * observation.endpoint_a_base_m);
  const double o_b = direction.dot(T_map_base * observation.endpoint_b_base_m);
  return std::max(o_a, o_b) >= std::min(s_a, s_b) - margin_m &&
         std::min(o_a, o_b) <= std::max(s_a, s_b) + margin_m;
}

bool ExtentsOverlap(const AtlasLine& a, const AtlasLine& b, double margin_m) {
  LineObservation seen;
  seen.line_base = a.line_map;
  seen.endpoint_a_base_m = a.endpoint_a_m;
  seen.endpoint_b_base_m = a.endpoint_b_m;
  return ExtentsOverlap(seen, b, core::SE2(), margin_m);
}

std::vector<Match> AssociateLines(const std::vector<LineObservation>& observations,
                                  const Atlas& atlas, const core::SE2& T_map_base,
                                  const core::Matrix3& pose_covariance,
                                  const AssociationOptions& options,
                                  const std::vector<bool>* excluded) {
  assert(excluded == nullptr || excluded->size() == atlas.lines.size());
  std::vector<Match> matches;
  for (size_t i = 0; i < observations.size(); ++i) {
    const LineObservation& observation = observations[i];
    matches.push_back(Select(
        static_cast<int>(i), static_cast<int>(atlas.lines.size()),
        [&](int j) {
          const AtlasLine& landmark = atlas.lines[j];
          if (excluded != nullptr && (*excluded)[j]) return std::numeric_limits<double>::infinity();
          if (!KindsCompatible(observation.kind, landmark.kind)) {
            return std::numeric_limits<double>::infinity();
          }
          if (!ExtentsOverlap(observation, landmark, T_map_base, options.extent_margin_m)) {
            return std::numeric_limits<double>::infinity();
          }
          return LineMahalanobis2(observation, landmark, T_map_base, pose_covariance);
        },
        [&](int a, int b) {
          const Eigen::Vector2d d =
              perception::LineDifference(atlas.lines[a].line_map, atlas.lines[b].line_map);
          return std::abs(d(0)) < options.duplicate_rho_m &&
                 std::abs(d(1)) < options.duplicate_alpha_rad;
        },
        options));
  }
  return matches;
}

std::vector<Match> AssociateJunctions(const std::vector<JunctionObservation>& observations,
                                      const Atlas& atlas, const core::SE2& T_map_base,
                                      const core::Matrix3& pose_covariance,
                                      const AssociationOptions& options,
                                      const std::vector<bool>* excluded) {
  assert(excluded == nullptr || excluded->size() == atlas.junctions.size());
  std::vector<Match> matches;
  for (size_t i = 0; i < observations.size(); ++i) {
    matches.push_back(Select(
        static_cast<int>(i), static_cast<int>(atlas.junctions.size()),
        [&](int j) {
          if (excluded != nullptr && (*excluded)[j]) return std::numeric_limits<double>::infinity();
          return JunctionMahalanobis2(observations[i], atlas.junctions[j], T_map_base,
                                      pose_covariance);
        },
        [&](int a, int b) {
          return (atlas.junctions[a].point_m - atlas.junctions[b].point_m).norm() <
                 options.duplicate_rho_m;
        },
        options));
  }
  return matches;
}

}  // namespace groundline::localization
