// The vehicle's odometry calibrated from one of its own drives: each wheel's
// effective radius, the effective track and the wheel noise, estimated from
// the wheel readings against the trajectory the localizer estimated from the
// floor lines and the LiDAR (a mapping drive, or any drive localized on an
// atlas). Nominal geometry from a drawing is off by tenths of a percent
// (tyre wear, load, where the contact patches carry the weight), and the noise
// defaults are generic; both decide how far the vehicle can trust its wheels
// between landmarks.
//
// The drive is cut into segments between well-localized keyframes, each at
// least min_segment_m of travel or min_segment_rad of turning. A segment's
// measurement is the estimated relative pose Z = T_a^-1 T_b; its prediction
// P(r_L, r_R, B) integrates the wheel readings over [t_a, t_b] with
// IncrementFromWheels (a reading that straddles an end is split in proportion
// to time: constant wheel rates within a reading). The residual
//   e = Log(P^-1 Z)
// has covariance S_odo(q, k_lat) + S_est: the odometry's own noise over the
// segment (OdometryIntegrator's propagation of OdometryNoiseFromWheelVariance,
// linear in the wheel variance q and the lateral variance k_lat) plus the
// estimate's (Between of the two keyframe covariances taken as independent:
// an upper bound, since the keyframes of one drive are positively correlated).
//
// 1. Geometry: (r_L, r_R, B) minimizing sum |L^-1 e|^2 (Ceres, Huber loss so
//    that a wheel slip moves nothing); the segments whose squared Mahalanobis
//    residual then exceeds outlier_chi2 (slips, a wrong association) are left
//    out and the fit repeated without a loss; its covariance is Ceres'.
//    Straight segments fix (r_R - r_L) / B and r_R + r_L; turns fix the track.
//    The lateral and heading rows are taken in wheel travel (times
//    B / B_nominal) so that their noise does not depend on the track being
//    fitted (without it the fit widens the track: errors in the variables).
// 2. Noise: (q, k_lat) by generalized least squares on the second moments of
//    the residuals of longer stretches (noise_segment_m),
//    E[e e^T] - S_est = q A + k_lat C (iteratively reweighted with
//    Var(e_j e_k) = S_jj S_kk + S_jk^2 of the current fit), clamped to stay
//    positive. 1 and 2 alternate twice, the second geometry fit weighted with
//    the estimated noise.
//
// The estimate's reliance on the localized trajectory is the point: run it on
// a drive localized on the atlas, not on dead reckoning, which would only
// return the geometry it was given.
#ifndef GROUNDLINE_LOCALIZATION_ODOMETRY_CALIBRATION_H_
#define GROUNDLINE_LOCALIZATION_ODOMETRY_CALIBRATION_H_

#include <filesystem>
#include <span>
#include <string>

#include "groundline/core/dataset_records.h"
#include "groundline/core/status.h"
#include "groundline/core/trajectory.h"
#include "groundline/localization/diff_drive_odometry.h"

namespace groundline::localization {

struct OdometryCalibrationOptions {
  double min_segment_m = 2.0;     // a segment closes after this much travel (axle midpoint) ...
  double min_segment_rad = 0.35;  // ... or this much net turning (20 deg)
  // The noise is fitted on longer stretches: the localized trajectory leans
  // on the odometry between keyframes, which shrinks short residuals; over a
  // long stretch the wheels' accumulated error dominates what the
  // localization's endpoints leave.
  double noise_segment_m = 8.0;
  double noise_segment_rad = 1.4;  // 80 deg
  // A segment never spans more time than this (a standstill, a gap in the
  // keyframes) [s].
  double max_segment_s = 60.0;
  // Both ends of a segment localized at least this well: the larger standard
  // deviation of the position covariance [m] and the heading's [rad].
  double max_pose_sigma_m = 0.03;
  double max_pose_sigma_rad = 0.005;
  // A segment whose squared Mahalanobis residual (3 dof) exceeds this after
  // the robust fit is an outlier (99.9 %).
  double outlier_chi2 = 16.27;
  // A differential drive has no lateral error of its own (its lateral error
  // is the heading's, carried along): the lateral variance stays the prior
  // and only the wheel variance is fitted. true: fit both (a vehicle with
  // side slip); on the simulated vehicle, which has none, the joint fit took
  // 10-30 % of the wheel variance into the lateral one.
  bool estimate_lateral_variance = false;
  // The noise the localizer assumed: the first geometry fit's weights.
  double prior_wheel_variance_m2_per_m = 1.0e-5;
  double prior_lateral_variance_m2_per_m = 1.0e-7;
  // Fewer inlier segments than this, or segments that never turn, cannot
  // separate the radii from the track: an error.
  int min_segments = 20;
  double min_total_rotation_rad =
      6.283185307179586;  // one full turn over the drive (sum of |net turn|)

  // Ok if every length, angle, time and variance is finite and > 0 and
  // min_segments >= 4; otherwise names the field and the value.
  core::Status Validate() const;
};

struct OdometryCalibration {
  // The calibrated geometry: left_wheel_radius_m, right_wheel_radius_m and
  // track_m estimated; wheel_radius_m is the nominal radius given.
  DiffDriveParams drive;
  // Covariance of (left radius, right radius, track) [m^2].
  core::Matrix3 drive_covariance = core::Matrix3::Zero();
  // The wheel travel variance per metre of that wheel's travel and the
  // lateral variance per metre (LocalizerOptions::wheel_variance_m2_per_m,
  // lateral_variance_m2_per_m), with their standard deviations (the lateral
  // one: the prior with sigma 0 unless estimate_lateral_variance).
  double wheel_variance_m2_per_m = 0.0;
  double wheel_variance_sigma_m2_per_m = 0.0;
  double lateral_variance_m2_per_m = 0.0;
  double lateral_variance_sigma_m2_per_m = 0.0;
  // What it was estimated from.
  int segments = 0;           // inliers used
  int segments_rejected = 0;  // outliers left out (slips)
  int poses_unlocalized = 0;  // keyframes too uncertain to end a segment
  double distance_m = 0.0;    // travel of the inlier segments
  double rotation_rad = 0.0;  // turning of the inlier segments (sum of each one's |net turn|)
  // Mean over the inlier segments of e^T S^-1 e / 3 with the final geometry
  // and noise: 1 when the noise model explains the residuals.
  double mean_normalized_chi2 = 0.0;
  // Where the drive came from (free text for the file, e.g. the dataset).
  std::string source;
};

// Errors: invalid options or nominal geometry; fewer than two localized
// keyframes with covariance; too few segments or too little turning (names
// what was found and what is needed); a fit that does not converge.
core::Result<OdometryCalibration> CalibrateOdometry(
    std::span<const core::WheelEncoderReading> readings, const DiffDriveParams& nominal,
    const core::Trajectory& localized, const OdometryCalibrationOptions& options = {});

// The calibration file (JSON, format "groundline-odometry-calibration"; docs/
// localization.md "Odometry calibration"), written atomically. Reading
// checks the format and that the radii, the track and the variances are
// finite and > 0; errors name the file and the field.
core::Status WriteOdometryCalibration(const std::filesystem::path& path,
                                      const OdometryCalibration& calibration);
core::Result<OdometryCalibration> ReadOdometryCalibration(const std::filesystem::path& path);

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_ODOMETRY_CALIBRATION_H_
