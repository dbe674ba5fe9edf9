#include "groundline/calibration/mount_from_parallels.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <optional>

#include "groundline/calibration/mount_remap.h"
#include "groundline/core/angles.h"
#include "groundline/core/statistics.h"

namespace groundline::calibration {
namespace {

// A segment's endpoints under the start mount with pitch and roll changed by
// c = (dpitch, droll); false beyond the horizon.
template <typename T>
bool Endpoints(const FloorSegment& s, const CameraMount& used, const CameraMount& start, const T* c,
               Eigen::Matrix<T, 2, 1>* a, Eigen::Matrix<T, 2, 1>* b) {
  const T zero(0.0);
  return RemapFloorPointCorrected<T>(s.start_m, used, start, c[0], c[1], zero, zero, a) &&
         RemapFloorPointCorrected<T>(s.end_m, used, start, c[0], c[1], zero, zero, b);
}

// sin (parallel) or cos (perpendicular) of the angle between two segments'
// directions under the candidate mount, over its sigma.
struct PairCost {
  PairCost(const FloorSegment& reference, const FloorSegment& other, const CameraMount& used,
           const CameraMount& start, bool perpendicular, double sigma)
      : reference_(reference),
        other_(other),
        used_(used),
        start_(start),
        perpendicular_(perpendicular),
        sigma_(sigma) {}

  template <typename T>
  bool operator()(const T* c, T* residual) const {
    Eigen::Matrix<T, 2, 1> ra, rb, oa, ob;
    if (!Endpoints(reference_, used_, start_, c, &ra, &rb) ||
        !Endpoints(other_, used_, start_, c, &oa, &ob))
      return false;
    const Eigen::Matrix<T, 2, 1> dr = (rb - ra).normalized(), d_o = (ob - oa).normalized();
    const T value = perpendicular_ ? dr.dot(d_o) : dr.x() * d_o.y() - dr.y() * d_o.x();
    residual[0] = value / T(sigma_);
    return true;
  }

  FloorSegment reference_, other_;
  CameraMount used_, start_;
  bool perpendicular_;
  double sigma_;
};

struct ChangePrior {
  ChangePrior(double pitch_sigma, double roll_sigma) : sigma_{pitch_sigma, roll_sigma} {}
  template <typename T>
  bool operator()(const T* c, T* residual) const {
    residual[0] = c[0] / T(sigma_[0]);
    residual[1] = c[1] / T(sigma_[1]);
    return true;
  }
  std::array<double, 2> sigma_;
};

// The angle's variance of a segment: its alpha variance, and the endpoint
// floor across its length.
double AngleVariance(const FloorSegment& s, double min_sigma_m) {
  const double length = (s.end_m - s.start_m).norm();
  const double floor = std::sqrt(2.0) * min_sigma_m / std::max(length, 1e-6);
  return std::max(s.covariance(1, 1), 0.0) + floor * floor;
}

double Length(const FloorSegment& s) { return (s.end_m - s.start_m).norm(); }

std::vector<LinePairAngle> Pairs(const std::vector<ParallelImage>& images, const CameraMount& start,
                                 const double* c, const MountFromParallelsOptions& o) {
  const double parallel_sin = std::sin(o.parallel_tolerance_deg * core::kDegToRad);
  const double perpendicular_cos = std::sin(o.perpendicular_tolerance_deg * core::kDegToRad);
  std::vector<LinePairAngle> pairs;
  for (std::size_t i = 0; i < images.size(); ++i) {
    const ParallelImage& image = images[i];
    // Directions under the candidate mount, and the reference: the longest.
    std::vector<std::optional<Eigen::Vector2d>> direction(image.segments.size());
    int reference = -1;
    double longest = 0.0;
    for (std::size_t k = 0; k < image.segments.size(); ++k) {
      const FloorSegment& s = image.segments[k];
      if (Length(s) < o.min_segment_length_m) continue;
      Eigen::Vector2d a, b;
      if (!Endpoints(s, image.mount_used, start, c, &a, &b) || (b - a).norm() < 1e-9) continue;
      direction[k] = (b - a).normalized();
      if ((b - a).norm() > longest) {
        longest = (b - a).norm();
        reference = static_cast<int>(k);
      }
    }
    if (reference < 0) continue;
    const Eigen::Vector2d& dr = *direction[reference];
    for (std::size_t k = 0; k < image.segments.size(); ++k) {
      if (static_cast<int>(k) == reference || !direction[k]) continue;
      const double sine = std::abs(dr.x() * direction[k]->y() - dr.y() * direction[k]->x());
      const double cosine = std::abs(dr.dot(*direction[k]));
      LinePairAngle p;
      p.image = static_cast<int>(i);
      p.reference = reference;
      p.other = static_cast<int>(k);
      if (sine <= parallel_sin) {
        p.off_deg = std::asin(std::min(sine, 1.0)) * core::kRadToDeg;
      } else if (o.use_perpendicular && cosine <= perpendicular_cos) {
        p.perpendicular = true;
        p.off_deg = std::asin(std::min(cosine, 1.0)) * core::kRadToDeg;
      } else {
        continue;  // oblique: no constraint
      }
      pairs.push_back(p);
    }
  }
  return pairs;
}

bool SamePairing(const std::vector<LinePairAngle>& a, const std::vector<LinePairAngle>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].image != b[i].image || a[i].reference != b[i].reference ||
        a[i].other != b[i].other || a[i].perpendicular != b[i].perpendicular)
      return false;
  }
  return true;
}

}  // namespace

core::Status MountFromParallelsOptions::Validate() const {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(parallel_tolerance_deg) || parallel_tolerance_deg >= 45.0)
    return core::Status::Error("parallel_tolerance_deg: expected in (0, 45), got " +
                               std::to_string(parallel_tolerance_deg));
  if (!positive(perpendicular_tolerance_deg) || perpendicular_tolerance_deg >= 45.0)
    return core::Status::Error("perpendicular_tolerance_deg: expected in (0, 45), got " +
                               std::to_string(perpendicular_tolerance_deg));
  if (!std::isfinite(min_segment_length_m) || min_segment_length_m < 0.0)
    return core::Status::Error("min_segment_length_m: expected >= 0");
  if (!std::isfinite(min_segment_sigma_m) || min_segment_sigma_m < 0.0)
    return core::Status::Error("min_segment_sigma_m: expected >= 0");
  if (!positive(pitch_prior_sigma_deg) || !positive(roll_prior_sigma_deg))
    return core::Status::Error("pitch_prior_sigma_deg, roll_prior_sigma_deg: expected > 0");
  if (!positive(loss_scale)) return core::Status::Error("loss_scale: expected > 0");
  if (max_rounds < 1) return core::Status::Error("max_rounds: expected >= 1");
  return core::Status::Ok();
}

std::vector<LinePairAngle> PairParallelLines(const std::vector<ParallelImage>& images,
                                             const CameraMount& mount,
                                             const MountFromParallelsOptions& options) {
  const double none[2] = {0.0, 0.0};
  return Pairs(images, mount, none, options);
}

core::Result<MountFromParallels> SolveMountFromParallels(const std::vector<ParallelImage>& images,
                                                         const CameraMount& start,
                                                         const MountFromParallelsOptions& o) {
  if (core::Status s = o.Validate(); !s.ok()) return core::Status::Error(s.message());
  if (core::Status s = start.Validate(); !s.ok())
    return core::Status::Error("the start mount: " + s.message());
  MountFromParallels out;
  out.pairs_before = PairParallelLines(images, start, o);
  if (out.pairs_before.empty())
    return core::Status::Error(
        "no image has two floor lines parallel or perpendicular (within " +
        std::to_string(static_cast<int>(std::lround(o.parallel_tolerance_deg))) + " and " +
        std::to_string(static_cast<int>(std::lround(o.perpendicular_tolerance_deg))) + " deg)");
  std::array<double, 2> c{0.0, 0.0};
  std::vector<LinePairAngle> pairing = out.pairs_before;
  std::unique_ptr<ceres::Problem> problem;
  for (int round = 0; round < o.max_rounds; ++round) {
    ++out.rounds;
    problem = std::make_unique<ceres::Problem>();
    for (const LinePairAngle& p : pairing) {
      const ParallelImage& image = images[p.image];
      const FloorSegment& r = image.segments[p.reference];
      const FloorSegment& s = image.segments[p.other];
      const double sigma = std::sqrt(AngleVariance(r, o.min_segment_sigma_m) +
                                     AngleVariance(s, o.min_segment_sigma_m));
      problem->AddResidualBlock(new ceres::AutoDiffCostFunction<PairCost, 1, 2>(new PairCost(
                                    r, s, image.mount_used, start, p.perpendicular, sigma)),
                                new ceres::CauchyLoss(round == 0 ? 10.0 * o.loss_scale
                                                                 : o.loss_scale),
                                c.data());
    }
    problem->AddResidualBlock(
        new ceres::AutoDiffCostFunction<ChangePrior, 2, 2>(new ChangePrior(
            o.pitch_prior_sigma_deg * core::kDegToRad, o.roll_prior_sigma_deg * core::kDegToRad)),
        nullptr, c.data());
    ceres::Solver::Options solver;
    solver.linear_solver_type = ceres::DENSE_QR;
    solver.max_num_iterations = 50;
    solver.num_threads = 1;
    ceres::Solver::Summary summary;
    ceres::Solve(solver, problem.get(), &summary);
    if (!summary.IsSolutionUsable())
      return core::Status::Error("the solve failed: " + summary.message);
    std::vector<LinePairAngle> next = Pairs(images, start, c.data(), o);
    if (round > 0 && SamePairing(next, pairing)) break;
    pairing = std::move(next);
  }
  ceres::Covariance::Options cov_options;
  cov_options.algorithm_type = ceres::DENSE_SVD;
  ceres::Covariance covariance(cov_options);
  const std::vector<std::pair<const double*, const double*>> blocks = {{c.data(), c.data()}};
  if (!covariance.Compute(blocks, problem.get()))
    return core::Status::Error("the covariance of pitch and roll is not defined");
  covariance.GetCovarianceBlock(c.data(), c.data(), out.covariance.data());
  out.mount = start;
  out.mount.pitch_rad += c[0];
  out.mount.roll_rad += c[1];
  out.pairs_after = Pairs(images, start, c.data(), o);
  return out;
}

double MaxOffDeg(const std::vector<LinePairAngle>& pairs) {
  double m = 0.0;
  for (const LinePairAngle& p : pairs) m = std::max(m, p.off_deg);
  return m;
}

double MedianOffDeg(const std::vector<LinePairAngle>& pairs) {
  if (pairs.empty()) return 0.0;
  std::vector<double> v;
  v.reserve(pairs.size());
  for (const LinePairAngle& p : pairs) v.push_back(p.off_deg);
  return core::Median(std::move(v));
}

}  // namespace groundline::calibration
