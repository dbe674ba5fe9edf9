// One window of the mount self-calibration (mount_self_calibration.h): the
// frames' segments associated into landmarks, the least-squares problem over
// the mount correction, the landmarks and the frames' poses, and the
// window's information about the mount.
#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "groundline/calibration/mount_remap.h"
#include "groundline/calibration/mount_self_calibration.h"

namespace groundline::calibration {
namespace {

// Distances of a segment's two endpoints, remapped under the candidate mount
// and moved into the window frame by the frame's pose (x, y, theta), from the
// landmark (rho, alpha); whitened by the endpoints' covariance.
struct ObservationCost {
  ObservationCost(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const CameraMount& used,
                  const CameraMount& reference, const Eigen::Matrix2d& sqrt_info)
      : a_(a), b_(b), used_(used), reference_(reference), sqrt_info_(sqrt_info) {}

  template <typename T>
  bool operator()(const T* c, const T* landmark, const T* pose, T* residual) const {
    Eigen::Matrix<T, 2, 1> qa, qb;
    if (!RemapFloorPointCorrected<T>(a_, used_, reference_, c[kMountPitch], c[kMountRoll],
                                     c[kMountHeight], c[kMountYaw], &qa) ||
        !RemapFloorPointCorrected<T>(b_, used_, reference_, c[kMountPitch], c[kMountRoll],
                                     c[kMountHeight], c[kMountYaw], &qb))
      return false;
    using std::cos;
    using std::sin;
    const T ct = cos(pose[2]), st = sin(pose[2]);
    const T ca = cos(landmark[1]), sa = sin(landmark[1]);
    Eigen::Matrix<T, 2, 1> r;
    for (int i = 0; i < 2; ++i) {
      const Eigen::Matrix<T, 2, 1>& q = i == 0 ? qa : qb;
      const T x = ct * q.x() - st * q.y() + pose[0];
      const T y = st * q.x() + ct * q.y() + pose[1];
      r(i) = ca * x + sa * y - landmark[0];
    }
    const Eigen::Matrix<T, 2, 1> whitened = sqrt_info_.cast<T>() * r;
    residual[0] = whitened(0);
    residual[1] = whitened(1);
    return true;
  }

  Eigen::Vector2d a_, b_;
  CameraMount used_, reference_;
  Eigen::Matrix2d sqrt_info_;
};

// One patch of floor texture seen from two frames: its point in the
// previous frame, remapped under the candidate mount and moved by the two
// frames' poses into the current frame, then seen as the current frame's BEV
// (its mount) shows it, must be where the current frame saw it. The residual
// is in the current BEV's own coordinates, where the tracking error is: in
// the candidate mount's floor coordinates it would scale with the candidate
// (a lower camera shrinks the view and the noise with it), and least squares
// would shrink the view to shrink the noise (a height biased low by about
// N sigma^2 over the odometry's scale information).
struct FlowCost {
  FlowCost(const Eigen::Vector2d& previous, const CameraMount& previous_used,
           const Eigen::Vector2d& current, const CameraMount& current_used,
           const CameraMount& reference, double inverse_sigma)
      : previous_(previous),
        current_(current),
        previous_used_(previous_used),
        current_used_(current_used),
        reference_(reference),
        inverse_sigma_(inverse_sigma) {}

  template <typename T>
  bool operator()(const T* c, const T* pose0, const T* pose1, T* residual) const {
    using std::cos;
    using std::sin;
    const T height = T(reference_.height_m) + c[kMountHeight];
    const T pitch = T(reference_.pitch_rad) + c[kMountPitch];
    const T roll = T(reference_.roll_rad) + c[kMountRoll];
    const T yaw = T(reference_.yaw_rad) + c[kMountYaw];
    Eigen::Matrix<T, 2, 1> q0;
    if (!RemapFloorPoint<T>(previous_, previous_used_, height, pitch, roll, yaw, reference_, &q0))
      return false;
    // Into the window frame by pose0, out of it into the current frame by pose1.
    const T c0 = cos(pose0[2]), s0 = sin(pose0[2]);
    const T wx = c0 * q0.x() - s0 * q0.y() + pose0[0];
    const T wy = s0 * q0.x() + c0 * q0.y() + pose0[1];
    const T c1 = cos(pose1[2]), s1 = sin(pose1[2]);
    const T dx = wx - pose1[0], dy = wy - pose1[1];
    const Eigen::Matrix<T, 2, 1> q1(c1 * dx + s1 * dy, -s1 * dx + c1 * dy);
    Eigen::Matrix<T, 2, 1> predicted;
    if (!RemapFloorPointBetween<T>(q1, reference_, height, pitch, roll, yaw,
                                   T(current_used_.height_m), T(current_used_.pitch_rad),
                                   T(current_used_.roll_rad), T(current_used_.yaw_rad),
                                   current_used_, &predicted))
      return false;
    residual[0] = (predicted.x() - current_.x()) * inverse_sigma_;
    residual[1] = (predicted.y() - current_.y()) * inverse_sigma_;
    return true;
  }

  Eigen::Vector2d previous_, current_;
  CameraMount previous_used_, current_used_, reference_;
  double inverse_sigma_;
};

// The odometry between two consecutive frames' poses.
struct OdometryCost {
  OdometryCost(const core::SE2& measured, double sigma_m, double sigma_rad)
      : measured_(measured), sigma_m_(sigma_m), sigma_rad_(sigma_rad) {}

  template <typename T>
  bool operator()(const T* p0, const T* p1, T* residual) const {
    using std::cos;
    using std::sin;
    const T c = cos(p0[2]), s = sin(p0[2]);
    const T dx = p1[0] - p0[0], dy = p1[1] - p0[1];
    residual[0] = (c * dx + s * dy - measured_.x()) / sigma_m_;
    residual[1] = (-s * dx + c * dy - measured_.y()) / sigma_m_;
    residual[2] = (p1[2] - p0[2] - measured_.yaw()) / sigma_rad_;
    return true;
  }

  core::SE2 measured_;
  double sigma_m_, sigma_rad_;
};

// Two landmarks at a known angle: l0's normal turned from l1's by angle_rad,
// either description (the atlas's angle; parallel markings: 0, the sin of
// the angle between them; perpendicular ones: -pi/2, its cos).
struct RelativeAngleCost {
  RelativeAngleCost(double angle_rad, double sigma_rad)
      : angle_rad_(angle_rad), sigma_rad_(sigma_rad) {}
  template <typename T>
  bool operator()(const T* l0, const T* l1, T* residual) const {
    using std::sin;
    residual[0] = sin(l0[1] - l1[1] - T(angle_rad_)) / sigma_rad_;
    return true;
  }
  double angle_rad_, sigma_rad_;
};

// Two parallel landmarks a known distance apart.
struct SpacingCost {
  SpacingCost(double sign, double spacing_m, double sigma_m)
      : sign_(sign), spacing_m_(spacing_m), sigma_m_(sigma_m) {}
  template <typename T>
  bool operator()(const T* l0, const T* l1, T* residual) const {
    using std::cos;
    residual[0] = (sign_ * (l0[0] - cos(l0[1] - l1[1]) * l1[0]) - spacing_m_) / sigma_m_;
    return true;
  }
  double sign_, spacing_m_, sigma_m_;
};

struct PriorCost {
  PriorCost(const MountVector& mean, const MountVector& sigma) : mean_(mean), sigma_(sigma) {}
  template <typename T>
  bool operator()(const T* c, T* residual) const {
    for (int i = 0; i < 4; ++i) residual[i] = (c[i] - mean_(i)) / sigma_(i);
    return true;
  }
  MountVector mean_, sigma_;
};

struct Observation {
  int frame = 0;
  const FloorSegment* segment = nullptr;
};

struct Landmark {
  std::array<double, 2> line{};  // rho_m, alpha_rad in the window frame: the parameter
  // The latest observation's line, which the next frame's segments are
  // compared with: a marking moves through the view by one frame's motion at
  // a time, so a mount still wrong (its scale, its warp) shifts it little
  // between frames, where it can shift it by centimetres across the window.
  std::array<double, 2> last_line{};
  std::vector<Observation> observations;
  int last_frame = -1;
  // The atlas line most of its sightings were associated with (none: unset).
  std::optional<MapLineRef> map_line;
};

// The line (rho, alpha) through two points; nullopt when they coincide.
std::optional<std::array<double, 2>> LineThrough(const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
  const Eigen::Vector2d d = q - p;
  const double length = d.norm();
  if (length < 1e-9) return std::nullopt;
  const Eigen::Vector2d n(-d.y() / length, d.x() / length);
  return std::array<double, 2>{n.dot(p), std::atan2(n.y(), n.x())};
}

// The endpoints' perpendicular-distance covariance from the segment's (rho,
// alpha) covariance: distance error = t dalpha - drho at along-line t.
Eigen::Matrix2d EndpointSqrtInformation(const FloorSegment& s, double min_sigma_m) {
  const Eigen::Vector2d d = (s.end_m - s.start_m).normalized();
  Eigen::Matrix2d J;
  J << -1.0, d.dot(s.start_m), -1.0, d.dot(s.end_m);
  Eigen::Matrix2d cov = J * s.covariance * J.transpose();
  cov.diagonal().array() += min_sigma_m * min_sigma_m;
  const Eigen::Matrix2d L = Eigen::LLT<Eigen::Matrix2d>(cov).matrixL();
  return L.inverse();
}

// Whether segment (in the window frame, as a line through pa, pb) is the
// landmark: direction within the gate and both endpoints near its line.
double AssociationDistance(const Landmark& l, const Eigen::Vector2d& pa, const Eigen::Vector2d& pb,
                           const MountSelfCalibrationOptions& o) {
  const auto seg = LineThrough(pa, pb);
  if (!seg) return -1.0;
  const std::array<double, 2>& line = l.last_line;
  if (std::abs(std::sin((*seg)[1] - line[1])) > std::sin(o.associate_max_angle_rad)) return -1.0;
  const Eigen::Vector2d n(std::cos(line[1]), std::sin(line[1]));
  const double da = std::abs(n.dot(pa) - line[0]), db = std::abs(n.dot(pb) - line[0]);
  if (std::max(da, db) > o.associate_max_distance_m) return -1.0;
  return da + db;
}

MountWindowSolution Failed(MountWindowSolution s, std::string message) {
  s.ok = false;
  s.message = std::move(message);
  return s;
}

// One solve with the regularizing prior centred on prior_correction.
MountWindowSolution SolveOnce(const std::vector<MountFrame>& frames, const CameraMount& reference,
                              const MountVector& prior_correction,
                              const MountSelfCalibrationOptions& o) {
  MountWindowSolution out;
  out.frames = static_cast<int>(frames.size());
  if (frames.size() < 2) return Failed(out, "fewer than two frames");
  const CameraMount prior_mount =
      WithMountComponents(reference, MountComponents(reference) + prior_correction);

  // Frames' poses in the window frame (the first frame's base_link).
  const core::SE2 T_first_odom = frames.front().T_odom_base.Inverse();
  std::vector<std::array<double, 3>> poses(frames.size());
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const core::SE2 T = T_first_odom * frames[k].T_odom_base;
    poses[k] = {T.x(), T.y(), T.yaw()};
  }

  // Associate segments into landmarks, remapped under the prior mount.
  std::vector<Landmark> landmarks;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const core::SE2 T(poses[k][0], poses[k][1], poses[k][2]);
    for (const FloorSegment& s : frames[k].segments) {
      if ((s.end_m - s.start_m).norm() < o.min_segment_length_m) continue;
      Eigen::Vector2d qa, qb;
      if (!RemapFloorPoint(s.start_m, frames[k].mount_used, prior_mount, &qa) ||
          !RemapFloorPoint(s.end_m, frames[k].mount_used, prior_mount, &qb))
        continue;
      const Eigen::Vector2d pa = T * qa, pb = T * qb;
      int best = -1;
      double best_distance = 0.0;
      for (std::size_t j = 0; j < landmarks.size(); ++j) {
        if (landmarks[j].last_frame == static_cast<int>(k)) continue;
        const double d = AssociationDistance(landmarks[j], pa, pb, o);
        if (d >= 0.0 && (best < 0 || d < best_distance)) {
          best = static_cast<int>(j);
          best_distance = d;
        }
      }
      if (best < 0) {
        const auto line = LineThrough(pa, pb);
        if (!line) continue;
        landmarks.push_back(Landmark{*line, *line, {}, -1, std::nullopt});
        best = static_cast<int>(landmarks.size()) - 1;
      } else if (const auto line = LineThrough(pa, pb)) {
        landmarks[best].last_line = *line;
      }
      landmarks[best].observations.push_back({static_cast<int>(k), &s});
      landmarks[best].last_frame = static_cast<int>(k);
    }
  }

  // Only markings tracked through several frames count: a segment seen once
  // is as likely clutter, a glare streak or the edge of something standing on
  // the floor, and a parallel tie to it would pull the mount.
  std::erase_if(landmarks, [&](const Landmark& l) {
    return static_cast<int>(l.observations.size()) < o.min_track_frames;
  });

  // The atlas line of each landmark: the one most of its sightings were
  // associated with, if at least min_track_frames of them were.
  if (o.use_map_geometry) {
    for (Landmark& l : landmarks) {
      std::vector<std::pair<const MapLineRef*, int>> counts;
      for (const Observation& obs : l.observations) {
        if (!obs.segment->map_line) continue;
        const MapLineRef& ref = *obs.segment->map_line;
        auto it = std::find_if(counts.begin(), counts.end(),
                               [&](const auto& c) { return c.first->id == ref.id; });
        if (it == counts.end()) {
          counts.emplace_back(&ref, 1);
        } else {
          ++it->second;
        }
      }
      const auto best =
          std::max_element(counts.begin(), counts.end(),
                           [](const auto& x, const auto& y) { return x.second < y.second; });
      if (best != counts.end() && best->second >= o.min_track_frames) l.map_line = *best->first;
    }
  }

  // Structure and spacing pairs among the landmarks.
  struct Pair {
    int a, b;
    bool perpendicular;
  };
  std::vector<Pair> structure;
  struct MapPair {
    int a, b;
    double angle_rad, angle_sigma_rad;
    std::optional<double> sign;                     // parallel: the window's signed gap's sign ..
    double spacing_m = 0.0, spacing_sigma_m = 0.0;  // .. and the atlas's distance
  };
  std::vector<MapPair> map_pairs;
  struct Spacing {
    int a, b;
    double sign, spacing_m;
  };
  std::vector<Spacing> spacings;
  const double gate = std::sin(o.structure_gate_rad);
  for (std::size_t a = 0; a < landmarks.size(); ++a) {
    for (std::size_t b = a + 1; b < landmarks.size(); ++b) {
      const double d = landmarks[a].line[1] - landmarks[b].line[1];
      const std::optional<MapLineRef>& ma = landmarks[a].map_line;
      const std::optional<MapLineRef>& mb = landmarks[b].map_line;
      if (ma && mb && ma->id != mb->id) {
        // Two atlas lines: the atlas's angle between them, as the window's
        // descriptions pair their normals (the atlas's turned by pi where
        // they disagree: the sine residual is indifferent to it).
        MapPair p{static_cast<int>(a), static_cast<int>(b), ma->alpha_rad - mb->alpha_rad,
                  std::sqrt(o.parallel_sigma_rad * o.parallel_sigma_rad +
                            ma->sigma_rad * ma->sigma_rad + mb->sigma_rad * mb->sigma_rad),
                  std::nullopt};
        if (std::abs(std::sin(p.angle_rad)) < gate && std::abs(std::sin(d)) < gate) {
          const double map_gap = ma->rho_m - std::cos(p.angle_rad) * mb->rho_m;
          const double signed_gap = landmarks[a].line[0] - std::cos(d) * landmarks[b].line[0];
          p.sign = signed_gap >= 0.0 ? 1.0 : -1.0;
          p.spacing_m = std::abs(map_gap);
          p.spacing_sigma_m = std::sqrt(o.map_spacing_sigma_m * o.map_spacing_sigma_m +
                                        ma->sigma_m * ma->sigma_m + mb->sigma_m * mb->sigma_m);
        }
        // The window's angle must be the atlas's within the structure gate
        // (else the association or the tracking is wrong: no tie).
        if (std::abs(std::sin(d - p.angle_rad)) < gate) {
          map_pairs.push_back(p);
          continue;
        }
      }
      if (std::abs(std::sin(d)) < gate) {
        structure.push_back({static_cast<int>(a), static_cast<int>(b), false});
        const double signed_gap = landmarks[a].line[0] - std::cos(d) * landmarks[b].line[0];
        for (double spacing : o.known_spacings_m) {
          if (std::abs(std::abs(signed_gap) - spacing) < o.spacing_gate_m) {
            spacings.push_back({static_cast<int>(a), static_cast<int>(b),
                                signed_gap >= 0.0 ? 1.0 : -1.0, spacing});
            break;
          }
        }
      } else if (o.use_perpendicular && std::abs(std::cos(d)) < gate) {
        structure.push_back({static_cast<int>(a), static_cast<int>(b), true});
      }
    }
  }

  // The problem.
  ceres::Problem problem;
  std::array<double, 4> c{};
  for (int i = 0; i < 4; ++i) c[i] = prior_correction(i);
  problem.AddParameterBlock(c.data(), 4);
  problem.AddResidualBlock(
      new ceres::AutoDiffCostFunction<PriorCost, 4, 4>(
          new PriorCost(prior_correction, o.window_prior_sigma)),
      nullptr, c.data());
  for (auto& p : poses) problem.AddParameterBlock(p.data(), 3);
  problem.SetParameterBlockConstant(poses.front().data());
  for (std::size_t k = 0; k + 1 < frames.size(); ++k) {
    const core::SE2 measured = frames[k].T_odom_base.Between(frames[k + 1].T_odom_base);
    const double sqrt_distance = std::sqrt(std::max(measured.translation().norm(), 0.01));
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<OdometryCost, 3, 3, 3>(
            new OdometryCost(measured, o.odometry_sigma_m_per_sqrt_m * sqrt_distance,
                             o.odometry_sigma_rad_per_sqrt_m * sqrt_distance)),
        nullptr, poses[k].data(), poses[k + 1].data());
  }
  if (o.use_floor_flow) {
    for (std::size_t k = 1; k < frames.size(); ++k) {
      const FloorFlow& flow = frames[k].flow;
      if (static_cast<int>(flow.points.size()) < o.min_flow_points ||
          !FlowFollows(flow, frames[k - 1]))
        continue;
      const CameraMount& current_mount = flow.current_mount.value_or(frames[k].mount_used);
      // The pairs whose points meet under the starting mount and the
      // odometry; at most max_flow_points of them, spread over the list.
      const core::SE2 T0(poses[k - 1][0], poses[k - 1][1], poses[k - 1][2]);
      const core::SE2 T1(poses[k][0], poses[k][1], poses[k][2]);
      std::vector<int> kept;
      for (std::size_t i = 0; i < flow.points.size(); ++i) {
        Eigen::Vector2d q0, q1;
        if (!RemapFloorPoint(flow.points[i].first, flow.previous_mount, prior_mount, &q0) ||
            !RemapFloorPoint(flow.points[i].second, current_mount, prior_mount, &q1))
          continue;
        if (((T1 * q1) - (T0 * q0)).norm() <= o.flow_gate_m) kept.push_back(static_cast<int>(i));
      }
      const int n = std::min(static_cast<int>(kept.size()), o.max_flow_points);
      if (n < o.min_flow_points) continue;
      const double inflation = 1.0 + o.flow_correlation * (n - 1.0);
      const double inverse_sigma = 1.0 / (o.flow_sigma_m * std::sqrt(inflation));
      for (int j = 0; j < n; ++j) {
        const auto& pair = flow.points[kept[static_cast<std::size_t>(j) * kept.size() / n]];
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<FlowCost, 2, 4, 3, 3>(
                                     new FlowCost(pair.first, flow.previous_mount, pair.second,
                                                  current_mount, reference, inverse_sigma)),
                                 new ceres::CauchyLoss(o.loss_scale), c.data(), poses[k - 1].data(),
                                 poses[k].data());
      }
      ++out.flow_pairs;
      out.flow_points += n;
    }
  }
  for (Landmark& l : landmarks) {
    ++out.landmarks;
    const double inflation =
        1.0 + o.track_correlation * (static_cast<double>(l.observations.size()) - 1.0);
    for (const Observation& obs : l.observations) {
      const FloorSegment& s = *obs.segment;
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<ObservationCost, 2, 4, 2, 3>(new ObservationCost(
              s.start_m, s.end_m, frames[obs.frame].mount_used, reference,
              EndpointSqrtInformation(s, o.min_segment_sigma_m) / std::sqrt(inflation))),
          new ceres::CauchyLoss(o.loss_scale), c.data(), l.line.data(), poses[obs.frame].data());
      ++out.observations;
    }
  }
  for (const Pair& p : structure) {
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<RelativeAngleCost, 1, 2, 2>(new RelativeAngleCost(
            p.perpendicular ? -0.5 * std::numbers::pi : 0.0, o.parallel_sigma_rad)),
        new ceres::CauchyLoss(o.loss_scale), landmarks[p.a].line.data(),
        landmarks[p.b].line.data());
  }
  for (const Spacing& s : spacings) {
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<SpacingCost, 1, 2, 2>(
            new SpacingCost(s.sign, s.spacing_m, o.spacing_sigma_m)),
        new ceres::CauchyLoss(o.loss_scale), landmarks[s.a].line.data(),
        landmarks[s.b].line.data());
  }
  for (const MapPair& p : map_pairs) {
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<RelativeAngleCost, 1, 2, 2>(
                                 new RelativeAngleCost(p.angle_rad, p.angle_sigma_rad)),
                             new ceres::CauchyLoss(o.loss_scale), landmarks[p.a].line.data(),
                             landmarks[p.b].line.data());
    if (!p.sign) continue;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<SpacingCost, 1, 2, 2>(
                                 new SpacingCost(*p.sign, p.spacing_m, p.spacing_sigma_m)),
                             new ceres::CauchyLoss(o.loss_scale), landmarks[p.a].line.data(),
                             landmarks[p.b].line.data());
    ++out.map_spacings;
  }
  out.structure_pairs = static_cast<int>(structure.size());
  out.spacing_pairs = static_cast<int>(spacings.size());
  out.map_pairs = static_cast<int>(map_pairs.size());
  if (landmarks.empty() && out.flow_pairs == 0) {
    return Failed(out, "no marking tracked through " + std::to_string(o.min_track_frames) +
                           " frames and no floor texture tracked");
  }

  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = o.max_solver_iterations;
  solver.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  out.iterations = static_cast<int>(summary.iterations.size());
  out.final_cost = summary.final_cost;
  if (summary.termination_type == ceres::FAILURE || !summary.IsSolutionUsable())
    return Failed(out, "the solve failed: " + summary.message);

  ceres::Covariance::Options cov_options;
  cov_options.algorithm_type = ceres::DENSE_SVD;
  cov_options.null_space_rank = -1;
  ceres::Covariance covariance(cov_options);
  const std::vector<std::pair<const double*, const double*>> blocks = {{c.data(), c.data()}};
  if (!covariance.Compute(blocks, &problem)) return Failed(out, "the covariance is not defined");
  MountMatrix posterior;
  covariance.GetCovarianceBlock(c.data(), c.data(), posterior.data());
  posterior = 0.5 * (posterior + posterior.transpose()).eval();
  const Eigen::LDLT<MountMatrix> ldlt(posterior);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive())
    return Failed(out, "the covariance is not positive definite");
  const MountMatrix posterior_information = ldlt.solve(MountMatrix::Identity());
  const MountMatrix prior_information =
      o.window_prior_sigma.array().square().inverse().matrix().asDiagonal();
  // The window's own information, PSD by construction up to rounding.
  const Eigen::SelfAdjointEigenSolver<MountMatrix> eig(posterior_information - prior_information);
  const MountVector values = eig.eigenvalues().cwiseMax(0.0);
  out.information = eig.eigenvectors() * values.asDiagonal() * eig.eigenvectors().transpose();
  for (int i = 0; i < 4; ++i) out.correction(i) = c[i];
  // Its own estimate, the prior's pull taken out (first order, see the header):
  // Lambda_w c_w = Lambda_post c_post - Lambda_prior c_prior.
  out.information_vector =
      posterior_information * out.correction - prior_information * prior_correction;
  out.ok = true;
  return out;
}

}  // namespace

bool FlowFollows(const FloorFlow& flow, const MountFrame& previous) {
  return std::abs(flow.previous_stamp_s - previous.stamp_s) < 1e-3;
}

MountWindowSolution SolveMountWindow(const std::vector<MountFrame>& frames,
                                     const CameraMount& reference,
                                     const MountVector& prior_correction,
                                     const MountSelfCalibrationOptions& o) {
  // The prior's pull is taken out to first order about the prior's centre,
  // which is exact only near the solution: after a step the window lies far
  // from the running estimate (a degree of pitch), and in the directions a
  // window sees weakly (pitch against height) the linear removal would
  // extrapolate far. So the window is solved again, associations included,
  // with the prior centred on its own solution until that moves no more than
  // a fiftieth of the prior's sigma.
  MountVector center = prior_correction;
  MountWindowSolution out;
  for (int round = 0; round < 4; ++round) {
    out = SolveOnce(frames, reference, center, o);
    if (!out.ok) return out;
    const double moved =
        (out.correction - center).cwiseQuotient(o.window_prior_sigma).cwiseAbs().maxCoeff();
    if (moved < 0.02) break;
    center = out.correction;
  }
  return out;
}

}  // namespace groundline::calibration
