#include "groundline/localization/odometry_calibration.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "groundline/core/angles.h"
#include "groundline/core/atomic_file.h"
#include "groundline/localization/odometry_integrator.h"

namespace groundline::localization {
namespace {

core::Status FieldError(const std::string& field, const std::string& expected, double value) {
  std::ostringstream out;
  out << "OdometryCalibrationOptions." << field << ": expected " << expected << ", got " << value;
  return core::Status::Error(out.str());
}

// One segment between two localized keyframes.
struct Segment {
  std::vector<WheelAngleIncrement> wheels;  // the readings over [t_a, t_b], ends split
  core::SE2 measured;                       // T_a^-1 T_b of the estimate
  core::Matrix3 estimate_covariance = core::Matrix3::Zero();   // of `measured`
  core::Matrix3 per_wheel_variance = core::Matrix3::Zero();    // S_odo for q = 1, k_lat = 0
  core::Matrix3 per_lateral_variance = core::Matrix3::Zero();  // S_odo for q = 0, k_lat = 1
  double distance_m = 0.0;
  double rotation_rad = 0.0;
};

DiffDriveParams WithGeometry(const DiffDriveParams& nominal, const double* x) {
  DiffDriveParams d = nominal;
  d.left_wheel_radius_m = x[0];
  d.right_wheel_radius_m = x[1];
  d.track_m = x[2];
  return d;
}

// The motion the wheels predict over a segment, and its covariance under
// `noise` (any valid noise; the mean does not depend on it).
RelativeMotion Integrate(const DiffDriveParams& drive, const OdometryNoiseParams& noise,
                         const std::vector<WheelAngleIncrement>& wheels) {
  OdometryIntegrator integrator(drive, noise);
  for (const WheelAngleIncrement& w : wheels) integrator.Integrate(w);
  return integrator.since_reset();
}

// Log(P^-1 Z): the mean motion only (the fits evaluate it many times; the
// covariance is computed once per segment).
core::Vector3 Residual(const Segment& s, const DiffDriveParams& drive) {
  const OdometryNoiseParams noise;
  core::SE2 predicted;
  for (const WheelAngleIncrement& w : s.wheels) {
    predicted = predicted * IncrementFromWheels(drive, noise, w).T_prev_curr;
  }
  return predicted.Between(s.measured).Log();
}

core::Matrix3 SegmentCovariance(const Segment& s, double q, double k_lat) {
  return q * s.per_wheel_variance + k_lat * s.per_lateral_variance + s.estimate_covariance;
}

// Residual of one segment whitened by a fixed covariance (numeric
// derivatives: the prediction is IncrementFromWheels composed over the
// readings, the one implementation of the kinematics).
struct SegmentCost {
  const Segment* segment;
  const DiffDriveParams* nominal;
  core::Matrix3 sqrt_information;
  bool operator()(const double* x, double* residual) const {
    // The heading's noise, and the lateral noise it causes, scale with 1 / B
    // (dtheta = (r_R dphi_R - r_L dphi_L) / B): rows measured in wheel travel
    // (times B / B_nominal) keep their noise independent of the track being
    // fitted. Whitened with the nominal covariance as they are, a wider
    // track would shrink the wheels' noise in every straight segment and the
    // fit would widen it (errors in the variables: +0.7 % on a simulated
    // 600 m loop with 3e-5 m^2/m of wheel noise).
    const core::Vector3 e = Residual(*segment, WithGeometry(*nominal, x));
    const double scale = x[2] / nominal->track_m;
    Eigen::Map<core::Vector3> out(residual);
    out = sqrt_information * core::Vector3(e(0), scale * e(1), scale * e(2));
    return true;
  }
};

core::Matrix3 SqrtInformation(const core::Matrix3& covariance) {
  Eigen::LLT<core::Matrix3> llt(covariance);
  const core::Matrix3 L = llt.matrixL();
  return L.inverse();
}

double Chi2(const Segment& s, const DiffDriveParams& drive, double q, double k_lat) {
  const core::Vector3 e = Residual(s, drive);
  return e.dot(SegmentCovariance(s, q, k_lat).ldlt().solve(e));
}

struct GeometryFit {
  double x[3];
  core::Matrix3 covariance = core::Matrix3::Zero();
  bool converged = false;
  std::string message;
};

// Fits (r_L, r_R, B) over the segments with `use[i]`, each weighted with its
// covariance under (q, k_lat); robust: Huber at 2 sigma.
GeometryFit FitGeometry(const std::vector<Segment>& segments, const std::vector<bool>& use,
                        const DiffDriveParams& nominal, const double* start, double q, double k_lat,
                        bool robust, bool want_covariance) {
  GeometryFit fit;
  std::copy(start, start + 3, fit.x);
  ceres::Problem problem;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    if (!use[i]) continue;
    auto* cost =
        new ceres::NumericDiffCostFunction<SegmentCost, ceres::CENTRAL, 3, 3>(new SegmentCost{
            &segments[i], &nominal, SqrtInformation(SegmentCovariance(segments[i], q, k_lat))});
    problem.AddResidualBlock(cost, robust ? new ceres::HuberLoss(2.0) : nullptr, fit.x);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 50;
  options.function_tolerance = 1e-12;
  options.parameter_tolerance = 1e-12;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  fit.converged = summary.IsSolutionUsable() && fit.x[0] > 0.0 && fit.x[1] > 0.0 && fit.x[2] > 0.0;
  fit.message = summary.BriefReport();
  if (fit.converged && want_covariance) {
    ceres::Covariance::Options covariance_options;
    covariance_options.algorithm_type = ceres::DENSE_SVD;
    ceres::Covariance covariance(covariance_options);
    std::vector<std::pair<const double*, const double*>> blocks = {{fit.x, fit.x}};
    if (covariance.Compute(blocks, &problem)) {
      double c[9];
      covariance.GetCovarianceBlock(fit.x, fit.x, c);
      fit.covariance = Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(c);
    } else {
      fit.converged = false;
      fit.message = "the radii and the track are not observable from these segments";
    }
  }
  return fit;
}

// Generalized least squares of the residuals' second moments on (q, k_lat).
struct NoiseFit {
  double q = 0.0, k_lat = 0.0;
  double sigma_q = 0.0, sigma_k_lat = 0.0;
};

// With estimate_lateral false, k_lat stays k_lat0 and only q is fitted.
NoiseFit FitNoise(const std::vector<Segment>& segments, const std::vector<bool>& use,
                  const DiffDriveParams& drive, double q0, double k_lat0, bool estimate_lateral) {
  constexpr double kMinQ = 1e-9, kMinLateral = 1e-10;
  std::vector<core::Vector3> residuals(segments.size());
  for (std::size_t i = 0; i < segments.size(); ++i) {
    if (use[i]) residuals[i] = Residual(segments[i], drive);
  }
  NoiseFit fit{q0, k_lat0};
  constexpr int kEntries[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
  for (int iteration = 0; iteration < 6; ++iteration) {
    Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
    Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
    for (std::size_t i = 0; i < segments.size(); ++i) {
      if (!use[i]) continue;
      const Segment& s = segments[i];
      const core::Matrix3 S = SegmentCovariance(s, fit.q, fit.k_lat);
      const core::Vector3& e = residuals[i];
      for (const auto& [j, k] : kEntries) {
        double y = e(j) * e(k) - s.estimate_covariance(j, k);
        Eigen::Vector2d x(s.per_wheel_variance(j, k), s.per_lateral_variance(j, k));
        if (!estimate_lateral) {
          y -= fit.k_lat * x(1);
          x(1) = 0.0;
        }
        const double variance = S(j, j) * S(k, k) + S(j, k) * S(j, k);
        if (!(variance > 0.0)) continue;
        normal += x * x.transpose() / variance;
        rhs += x * y / variance;
      }
    }
    if (!estimate_lateral) {
      fit.q = std::max(kMinQ, rhs(0) / normal(0, 0));
      fit.sigma_q = std::sqrt(1.0 / normal(0, 0));
      continue;
    }
    const Eigen::Vector2d theta = normal.ldlt().solve(rhs);
    const Eigen::Matrix2d cov = normal.inverse();
    fit.q = std::max(kMinQ, theta(0));
    fit.k_lat = std::max(kMinLateral, theta(1));
    fit.sigma_q = std::sqrt(std::max(0.0, cov(0, 0)));
    fit.sigma_k_lat = std::sqrt(std::max(0.0, cov(1, 1)));
  }
  return fit;
}

// Cuts the readings into segments between consecutive anchors, each closed
// once it spans min_m of travel or min_rad of net turning. A reading covers
// (t_prev, t]; the first reading's span starts at its own stamp (nothing
// before it is known).
std::vector<Segment> BuildSegments(std::span<const core::WheelEncoderReading> readings,
                                   const DiffDriveParams& nominal_drive,
                                   const std::vector<const core::StampedPose*>& anchors,
                                   double min_m, double min_rad,
                                   const OdometryCalibrationOptions& options) {
  std::vector<Segment> segments;
  std::size_t r = 0;  // first reading not wholly before the current time
  std::size_t a = 0;
  Segment current;
  double t_from = anchors[0]->stamp_s;
  for (std::size_t b = 1; b < anchors.size(); ++b) {
    const double t_to = anchors[b]->stamp_s;
    // The readings' parts in (t_from, t_to].
    while (r < readings.size() && readings[r].stamp_s <= t_from) ++r;
    std::size_t k = r;
    for (; k < readings.size(); ++k) {
      const double t1 = readings[k].stamp_s;
      const double t0 = k > 0 ? readings[k - 1].stamp_s : t1;
      if (t0 >= t_to) break;
      const double span = t1 - t0;
      const double lo = std::max(t0, t_from), hi = std::min(t1, t_to);
      const double f = span > 0.0 ? std::clamp((hi - lo) / span, 0.0, 1.0) : 1.0;
      if (f <= 0.0) continue;
      const WheelAngleIncrement w{f * readings[k].left_delta_rad, f * readings[k].right_delta_rad};
      current.wheels.push_back(w);
      const OdometryIncrement inc = IncrementFromWheels(nominal_drive, OdometryNoiseParams{}, w);
      current.distance_m += std::abs(inc.distance_m);
      current.rotation_rad += inc.rotation_rad;  // net; made absolute when the segment closes
    }
    t_from = t_to;
    const double elapsed = t_to - anchors[a]->stamp_s;
    if (elapsed > options.max_segment_s || k >= readings.size()) {
      // Too long to be one measurement (or past the readings): start afresh here.
      current = Segment{};
      a = b;
      continue;
    }
    if (current.distance_m < min_m && std::abs(current.rotation_rad) < min_rad) continue;
    current.rotation_rad = std::abs(current.rotation_rad);
    core::Matrix3 J_a, J_b;
    current.measured = anchors[a]->pose.Between(anchors[b]->pose, &J_a, &J_b);
    current.estimate_covariance = J_a * (*anchors[a]->covariance) * J_a.transpose() +
                                  J_b * (*anchors[b]->covariance) * J_b.transpose();
    // The odometry noise over the segment, linear in (q, k_lat): S(q, k) =
    // q A + k C, from two propagations at the nominal geometry.
    const core::Matrix3 s11 =
        Integrate(nominal_drive, OdometryNoiseFromWheelVariance(1.0, nominal_drive.track_m, 1.0),
                  current.wheels)
            .covariance;
    const core::Matrix3 s12 =
        Integrate(nominal_drive, OdometryNoiseFromWheelVariance(1.0, nominal_drive.track_m, 2.0),
                  current.wheels)
            .covariance;
    current.per_lateral_variance = s12 - s11;
    current.per_wheel_variance = s11 - current.per_lateral_variance;
    segments.push_back(std::move(current));
    current = Segment{};
    a = b;
  }
  return segments;
}

double LargerSigma(const core::Matrix3& covariance) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(covariance.topLeftCorner<2, 2>());
  return std::sqrt(std::max(0.0, eig.eigenvalues().maxCoeff()));
}

}  // namespace

core::Status OdometryCalibrationOptions::Validate() const {
  const struct {
    const char* name;
    double value;
  } positive[] = {{"min_segment_m", min_segment_m},
                  {"min_segment_rad", min_segment_rad},
                  {"noise_segment_m", noise_segment_m},
                  {"noise_segment_rad", noise_segment_rad},
                  {"max_segment_s", max_segment_s},
                  {"max_pose_sigma_m", max_pose_sigma_m},
                  {"max_pose_sigma_rad", max_pose_sigma_rad},
                  {"outlier_chi2", outlier_chi2},
                  {"prior_wheel_variance_m2_per_m", prior_wheel_variance_m2_per_m},
                  {"prior_lateral_variance_m2_per_m", prior_lateral_variance_m2_per_m},
                  {"min_total_rotation_rad", min_total_rotation_rad}};
  for (const auto& p : positive) {
    if (!(std::isfinite(p.value) && p.value > 0.0)) {
      return FieldError(p.name, "a finite value > 0", p.value);
    }
  }
  if (min_segments < 4) return FieldError("min_segments", "an integer >= 4", min_segments);
  return core::Status::Ok();
}

core::Result<OdometryCalibration> CalibrateOdometry(
    std::span<const core::WheelEncoderReading> readings, const DiffDriveParams& nominal,
    const core::Trajectory& localized, const OdometryCalibrationOptions& options) {
  if (core::Status s = options.Validate(); !s.ok()) return s;
  if (core::Status s = nominal.Validate(); !s.ok()) return s.WithContext("nominal geometry");
  OdometryCalibration out;

  // The keyframes localized well enough to end a segment.
  std::vector<const core::StampedPose*> anchors;
  for (const core::StampedPose& p : localized) {
    const bool good = p.covariance && LargerSigma(*p.covariance) <= options.max_pose_sigma_m &&
                      std::sqrt(std::max(0.0, (*p.covariance)(2, 2))) <= options.max_pose_sigma_rad;
    if (good && (anchors.empty() || p.stamp_s > anchors.back()->stamp_s)) {
      anchors.push_back(&p);
    } else if (!good) {
      ++out.poses_unlocalized;
    }
  }
  if (anchors.size() < 2) {
    return core::Status::Error("odometry calibration: " + std::to_string(anchors.size()) +
                               " keyframes localized within the pose sigma limits (" +
                               std::to_string(localized.size()) +
                               " given): needs a drive localized on the atlas, with covariances");
  }

  const std::vector<Segment> segments = BuildSegments(
      readings, nominal, anchors, options.min_segment_m, options.min_segment_rad, options);
  const std::vector<Segment> long_segments = BuildSegments(
      readings, nominal, anchors, options.noise_segment_m, options.noise_segment_rad, options);

  const auto count_rotation = [&](const std::vector<bool>& use) {
    double total = 0.0;
    for (std::size_t i = 0; i < segments.size(); ++i)
      if (use[i]) total += segments[i].rotation_rad;
    return total;
  };
  std::vector<bool> use(segments.size(), true);
  const auto check_enough = [&](const std::vector<bool>& u) -> core::Status {
    const int n = static_cast<int>(std::count(u.begin(), u.end(), true));
    if (n < options.min_segments) {
      std::ostringstream msg;
      msg << "odometry calibration: " << n << " usable segments of the drive (needs "
          << options.min_segments << ", each " << options.min_segment_m
          << " m between keyframes localized on the atlas)";
      return core::Status::Error(msg.str());
    }
    if (count_rotation(u) < options.min_total_rotation_rad) {
      std::ostringstream msg;
      msg << "odometry calibration: the drive turns "
          << count_rotation(u) * core::kRadToDeg << " deg in all (needs "
          << options.min_total_rotation_rad * core::kRadToDeg
          << "): without turns the track cannot be told from the radii";
      return core::Status::Error(msg.str());
    }
    return core::Status::Ok();
  };
  if (core::Status s = check_enough(use); !s.ok()) return s;

  double q = options.prior_wheel_variance_m2_per_m;
  double k_lat = options.prior_lateral_variance_m2_per_m;
  double x[3] = {nominal.LeftRadius(), nominal.RightRadius(), nominal.track_m};
  GeometryFit fit;
  NoiseFit noise;
  for (int round = 0; round < 2; ++round) {
    const GeometryFit robust = FitGeometry(segments, std::vector<bool>(segments.size(), true),
                                           nominal, x, q, k_lat, /*robust=*/true, false);
    if (!robust.converged) {
      return core::Status::Error("odometry calibration: the robust fit failed: " + robust.message);
    }
    const DiffDriveParams robust_drive = WithGeometry(nominal, robust.x);
    for (std::size_t i = 0; i < segments.size(); ++i) {
      use[i] = Chi2(segments[i], robust_drive, q, k_lat) <= options.outlier_chi2;
    }
    if (core::Status s = check_enough(use); !s.ok()) return s;
    fit = FitGeometry(segments, use, nominal, robust.x, q, k_lat, /*robust=*/false, true);
    if (!fit.converged) return core::Status::Error("odometry calibration: " + fit.message);
    std::copy(fit.x, fit.x + 3, x);
    const DiffDriveParams drive = WithGeometry(nominal, x);
    std::vector<bool> long_use(long_segments.size());
    for (std::size_t i = 0; i < long_segments.size(); ++i) {
      long_use[i] = Chi2(long_segments[i], drive, q, k_lat) <= options.outlier_chi2;
    }
    if (std::count(long_use.begin(), long_use.end(), true) < 4) {
      std::ostringstream msg;
      msg << "odometry calibration: fewer than 4 stretches of " << options.noise_segment_m
          << " m between localized keyframes to estimate the wheel noise from";
      return core::Status::Error(msg.str());
    }
    noise = FitNoise(long_segments, long_use, drive, q, k_lat, options.estimate_lateral_variance);
    q = noise.q;
    k_lat = noise.k_lat;
  }

  out.drive = WithGeometry(nominal, x);
  out.drive_covariance = fit.covariance;
  out.wheel_variance_m2_per_m = noise.q;
  out.wheel_variance_sigma_m2_per_m = noise.sigma_q;
  out.lateral_variance_m2_per_m = noise.k_lat;
  out.lateral_variance_sigma_m2_per_m = noise.sigma_k_lat;
  double chi2 = 0.0;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    if (use[i]) {
      ++out.segments;
      out.distance_m += segments[i].distance_m;
      out.rotation_rad += segments[i].rotation_rad;
      chi2 += Chi2(segments[i], out.drive, q, k_lat);
    } else {
      ++out.segments_rejected;
    }
  }
  out.mean_normalized_chi2 = chi2 / (3.0 * out.segments);
  return out;
}

namespace {
constexpr const char* kFormat = "groundline-odometry-calibration";
}  // namespace

core::Status WriteOdometryCalibration(const std::filesystem::path& path,
                                      const OdometryCalibration& c) {
  nlohmann::ordered_json j;
  j["format"] = kFormat;
  j["version"] = "1.0";
  j["source"] = c.source;
  j["left_wheel_radius_m"] = c.drive.LeftRadius();
  j["right_wheel_radius_m"] = c.drive.RightRadius();
  j["track_m"] = c.drive.track_m;
  j["nominal_wheel_radius_m"] = c.drive.wheel_radius_m;
  nlohmann::ordered_json cov = nlohmann::ordered_json::array();
  for (int i = 0; i < 3; ++i) {
    cov.push_back({c.drive_covariance(i, 0), c.drive_covariance(i, 1), c.drive_covariance(i, 2)});
  }
  j["covariance_left_right_track_m2"] = cov;
  j["wheel_variance_m2_per_m"] = c.wheel_variance_m2_per_m;
  j["wheel_variance_sigma_m2_per_m"] = c.wheel_variance_sigma_m2_per_m;
  j["lateral_variance_m2_per_m"] = c.lateral_variance_m2_per_m;
  j["lateral_variance_sigma_m2_per_m"] = c.lateral_variance_sigma_m2_per_m;
  j["segments"] = c.segments;
  j["segments_rejected"] = c.segments_rejected;
  j["poses_unlocalized"] = c.poses_unlocalized;
  j["distance_m"] = c.distance_m;
  j["rotation_deg"] = c.rotation_rad * core::kRadToDeg;
  j["mean_normalized_chi2"] = c.mean_normalized_chi2;
  return core::WriteFileAtomically(path, j.dump(2) + "\n");
}

core::Result<OdometryCalibration> ReadOdometryCalibration(const std::filesystem::path& path) {
  const std::string where = path.string();
  std::ifstream in(path);
  if (!in) return core::Status::Error(where + ": cannot open the odometry calibration file");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    return core::Status::Error(where + ": not JSON: " + e.what());
  }
  if (!j.is_object() || j.value("format", std::string()) != kFormat) {
    return core::Status::Error(where + ": field 'format': expected \"" + kFormat + "\"");
  }
  const auto number = [&](const char* field, bool required, double* value) -> core::Status {
    if (!j.contains(field)) {
      if (!required) return core::Status::Ok();
      return core::Status::Error(where + ": field '" + field + "' is missing");
    }
    if (!j[field].is_number() || !std::isfinite(j[field].get<double>()) ||
        !(j[field].get<double>() > 0.0)) {
      return core::Status::Error(where + ": field '" + field +
                                 "': expected a finite number > 0, got " + j[field].dump());
    }
    *value = j[field].get<double>();
    return core::Status::Ok();
  };
  OdometryCalibration c;
  for (const auto& [field, value] :
       {std::pair{"left_wheel_radius_m", &c.drive.left_wheel_radius_m},
        std::pair{"right_wheel_radius_m", &c.drive.right_wheel_radius_m},
        std::pair{"track_m", &c.drive.track_m},
        std::pair{"wheel_variance_m2_per_m", &c.wheel_variance_m2_per_m},
        std::pair{"lateral_variance_m2_per_m", &c.lateral_variance_m2_per_m}}) {
    if (core::Status s = number(field, true, value); !s.ok()) return s;
  }
  c.drive.wheel_radius_m = 0.5 * (c.drive.left_wheel_radius_m + c.drive.right_wheel_radius_m);
  if (core::Status s = number("nominal_wheel_radius_m", false, &c.drive.wheel_radius_m); !s.ok())
    return s;
  c.source = j.value("source", std::string());
  if (j.contains("covariance_left_right_track_m2")) {
    const nlohmann::json& m = j["covariance_left_right_track_m2"];
    bool ok = m.is_array() && m.size() == 3;
    for (int r = 0; ok && r < 3; ++r) {
      ok = m[r].is_array() && m[r].size() == 3;
      for (int k = 0; ok && k < 3; ++k) {
        ok = m[r][k].is_number() && std::isfinite(m[r][k].get<double>());
        if (ok) c.drive_covariance(r, k) = m[r][k].get<double>();
      }
    }
    if (!ok) {
      return core::Status::Error(where +
                                 ": field 'covariance_left_right_track_m2': expected a 3x3 "
                                 "array of finite numbers");
    }
  }
  c.wheel_variance_sigma_m2_per_m = j.value("wheel_variance_sigma_m2_per_m", 0.0);
  c.lateral_variance_sigma_m2_per_m = j.value("lateral_variance_sigma_m2_per_m", 0.0);
  c.segments = j.value("segments", 0);
  c.segments_rejected = j.value("segments_rejected", 0);
  c.poses_unlocalized = j.value("poses_unlocalized", 0);
  c.distance_m = j.value("distance_m", 0.0);
  c.rotation_rad = j.value("rotation_deg", 0.0) * core::kDegToRad;
  c.mean_normalized_chi2 = j.value("mean_normalized_chi2", 0.0);
  return c;
}

}  // namespace groundline::localization
