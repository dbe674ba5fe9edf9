// Straight vertical faces (rack faces, walls) in one planar LiDAR scan, as
// lines in Hesse normal form in base_link with a (rho, alpha) covariance from
// the range noise: the LiDAR counterpart of a floor line. A face constrains
// the lateral offset and the heading and carries nothing along itself.
//
// Fit (FitWallLine). Weighted total least squares (perception::FitLineTls)
// over points p_i with covariance C_i = sigma_r^2 u_i u_i^T + sigma_f^2 I
// (u_i: the unit ray direction, sigma_r: range noise, sigma_f: an isotropic
// floor for face roughness), weights w_i = 1 / (n^T C_i n): a ray grazing the
// face measures it better than one hitting it square on. The covariance is
// first order, Sigma = sum_i J_i C_i J_i^T, with J_i = d(rho, alpha)/d(p_i)
// from the implicit function theorem on the two stationarity conditions of
// the weighted TLS cost (e_i = n.p_i - rho, t_i = d.p_i, d the direction):
//   H1 = sum w_i e_i = 0,   H2 = sum w_i e_i t_i = 0,
//   J_i = -A^-1 B_i,  A = [[-W, sum w t], [-sum w t, sum w (t^2 - e n.p)]],
//   B_i = w_i [n^T; t_i n^T + e_i d^T].
//
// Extraction (ExtractWallLines), per scan:
//  1. RANSAC (fixed seed, so a scan always gives the same lines) over the
//     points within max_range_m: the line through two points with the most
//     points within +-band_m (wide enough to hold pallets recessed a few
//     centimetres behind the upright faces);
//  2. the band is split where it has a gap above max_gap_m along the line (a
//     doorway; the long shadow of a pedestrian near the sensor) and its run
//     with the most points must be a long structure: min_inliers points
//     spanning min_length_m;
//  3. the direction: FitWallLine on the whole band (upright faces and the
//     loads behind them are parallel);
//  4. the offset, along that direction (1-D), with s_i the signed distance
//     (smaller nearer the sensor) and sigma_i the point's noise across the
//     line (range noise along the ray, projected, and the face floor):
//     a. the band's centre c: from the weighted median of s, iterated
//        symmetric gating, c <- the weighted mean of the s_i with
//        |s_i - c| <= gate_sigma sigma_i. On a unimodal band (a plain wall)
//        the gate cuts both tails alike, so c is unbiased (an iteration
//        shrinks an offset d of c to ~0.09 d at gate_sigma 2.5);
//     b. a plain wall is a band with fewer than recess_min_points points
//        more than recess_sigma sigma_i off c on either side and at least
//        centre_min_fraction of its points within the gate: the face's
//        points are the gated ones, the offset c;
//     c. otherwise the band is recessed (a rack face: uprights in front of
//        loads a few centimetres behind with many more points, which pull c
//        back) and the offset is the band's front: c_front is the
//        (front_rank + 1)-th smallest s_i + front_sigma sigma_i and the
//        face's points are those with s_i - front_sigma sigma_i <= c_front,
//        the loads drop out however many points they have. The selection
//        is one-sided (a plain wall's front sits ~1 sigma of the square-on
//        rays in front of it, hence 4b) but on rack faces the uprights'
//        side faces, also among the front points, balance it: within 3 mm
//        (tests; +0.9 mm mean on zone B's racks at the true pose). The
//        front's own direction (FitWallLine on its points) must agree with
//        the band's within front_tilt_sigma times their combined alpha
//        sigma (plus front_tilt_slack_rad), else the band is dropped: a band
//        over two faces at different offsets (zone C's dock wall and its
//        doors 10 cm behind) fits a direction between them, and its front
//        came out 2-3 cm off at the true pose. The test is strict (0.5
//        sigma): it also drops ~12 % of zone B's rack bands.
//     The face's points must number min_face_inliers over min_face_span_m
//     (two uprights); the line moves to their weighted mean distance (rho's
//     variance gains 1 / sum 1/sigma_i^2). The band's points are removed and
//     the search repeats (at most max_lines lines). The line's extent is the
//     band's.
// The measurement covariance is the fit's plus diag(floor^2,
// face_alpha_sigma_rad^2), floor = face_rho_sigma_m for a plain wall (4b),
// recessed_rho_sigma_m for a recessed band (4c): what the point noise does
// not capture (an upright's side face among the front points, the survey of
// the face, mixed bands that pass 4c). The offset floors are set at the
// residual of the used faces at the true pose (plain walls 1.5-2.3 mm RMS,
// zone B's rack fronts 5.9 mm). The direction's floor is twice its residual
// (0.9 mrad): a face's direction error is the same from keyframe to
// keyframe (the same uprights, the same loads), and the smoother's window
// counts each sighting as independent; at the residual itself the heading
// came out about 2.4 times overconfident in the rack zones. How each floor
// was measured, and what the others did: docs/2026-12-06-wall-face-floors.md.
//
// Pure functions; thread-safe.
#ifndef GROUNDLINE_LOCALIZATION_LIDAR_WALL_LINES_H_
#define GROUNDLINE_LOCALIZATION_LIDAR_WALL_LINES_H_

#include <Eigen/Core>
#include <span>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/localization/floor_observation.h"
#include "groundline/perception/hesse_line.h"

namespace groundline::localization::lidar {

// One LiDAR return in the caller's frame (base_link): the point and the unit
// direction of the ray that measured it (the range noise acts along it).
struct RangePoint {
  core::Vector2 point_m = core::Vector2::Zero();
  core::Vector2 ray_direction = core::Vector2::UnitX();
};

struct WallLineFit {
  perception::HesseLine line;
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();  // (rho_m, alpha_rad)
  double rms_residual_m = 0.0;                           // weighted, orthogonal
};

// d(rho, alpha)/d(points) of the weighted TLS line `line` (as FitLineTls
// returns it, normalized) through the points with the given weights:
// 2 x 2N, columns (x_0, y_0, x_1, y_1, ...).
Eigen::Matrix<double, 2, Eigen::Dynamic> WeightedTlsJacobian(
    const perception::HesseLine& line, std::span<const Eigen::Vector2d> points_m,
    std::span<const double> weights);

// The fit above. Fails for fewer than two points, points that span no
// direction, non-positive sigmas.
core::Result<WallLineFit> FitWallLine(std::span<const RangePoint> points, double range_sigma_m,
                                      double face_sigma_m);

struct WallLineOptions {
  double range_sigma_m = 0.015;  // LiDAR range noise (1 sigma)
  double face_sigma_m = 0.003;   // isotropic per-point floor
  double min_range_m = 0.2;
  double max_range_m = 12.0;
  double band_m = 0.08;  // RANSAC inlier band, +-
  double front_sigma = 1.0;
  int front_rank = 2;
  double gate_sigma = 2.5;           // symmetric gate about the face, in point sigmas
  double recess_sigma = 3.0;         // a point this far off the band's centre is off it
  int recess_min_points = 4;         // points off it on one side that make a recess
  double centre_min_fraction = 0.8;  // of the band within the gate, for a plain wall
  double front_tilt_sigma = 0.5;     // recessed: front direction off the band's, in sigmas
  double min_length_m = 3.0;
  double max_gap_m = 3.0;
  int min_inliers = 12;
  int min_face_inliers = 6;
  double min_face_span_m = 2.0;
  int ransac_iterations = 150;
  int max_lines = 4;
  double face_rho_sigma_m = 0.003;
  double recessed_rho_sigma_m = 0.006;
  double face_alpha_sigma_rad = 0.002;
  double front_tilt_slack_rad = 0.002;  // step 4c's test
  unsigned seed = 1;

  core::Status Validate() const;
};

struct WallLine {
  WallLineFit fit;
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();  // fit + face floor
  core::Vector2 endpoint_a_m = core::Vector2::Zero();    // extent of the inliers, on the line
  core::Vector2 endpoint_b_m = core::Vector2::Zero();
  int num_inliers = 0;
  bool recessed = false;  // offset from the band's front (step 4c), not its centre
};

// The faces in one scan (options asserted valid), longest support first.
std::vector<WallLine> ExtractWallLines(std::span<const RangePoint> points,
                                       const WallLineOptions& options);

// As LineObservations for the smoother: kind kRackFace for a recessed band
// (its offset from the front), kWall for a plain one.
std::vector<LineObservation> WallLineObservations(const std::vector<WallLine>& walls);

// The scan's returns in base_link at the stamp of T_odom_base_ref, each ray
// moved by the odometry between its own time and that stamp (deskewing):
// ray i at angle_min_rad + i * angle_increment_rad, measured at
// scan_stamp_s + i * time_increment_s; odometry(t) gives T_odom_base(t).
// Ranges that are not finite or outside [min_range_m, max_range_m] are skipped.
template <typename Odometry>
std::vector<RangePoint> RangePointsAt(const std::vector<double>& ranges_m, double angle_min_rad,
                                      double angle_increment_rad, double scan_stamp_s,
                                      double time_increment_s, const core::SE2& T_base_lidar,
                                      const core::SE2& T_odom_base_ref, const Odometry& odometry,
                                      double min_range_m, double max_range_m) {
  std::vector<RangePoint> out;
  out.reserve(ranges_m.size());
  const core::SE2 T_ref_odom = T_odom_base_ref.Inverse();
  for (std::size_t i = 0; i < ranges_m.size(); ++i) {
    const double r = ranges_m[i];
    if (!(r >= min_range_m && r <= max_range_m)) continue;
    const double a = angle_min_rad + static_cast<double>(i) * angle_increment_rad;
    const core::SE2 T_ref_lidar =
        T_ref_odom * odometry(scan_stamp_s + static_cast<double>(i) * time_increment_s) *
        T_base_lidar;
    const core::Vector2 u(std::cos(a), std::sin(a));
    out.push_back({T_ref_lidar * core::Vector2(r * u), T_ref_lidar.Rotation() * u});
  }
  return out;
}

}  // namespace groundline::localization::lidar

#endif  // GROUNDLINE_LOCALIZATION_LIDAR_WALL_LINES_H_
