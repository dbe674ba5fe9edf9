#include "groundline/localization/lidar/wall_lines.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace groundline::localization::lidar {
namespace {

using perception::HesseLine;

core::Status Positive(const char* field, double value) {
  if (value > 0.0 && std::isfinite(value)) return core::Status::Ok();
  return core::Status::Error(std::string("WallLineOptions.") + field +
                             ": expected a finite value > 0, got " + std::to_string(value));
}

// The line c = n.p with n oriented along the rays (away from the sensor), so
// that a smaller signed distance is nearer the sensor.
struct OrientedLine {
  Eigen::Vector2d n;
  double c = 0.0;
  double Distance(const Eigen::Vector2d& p) const { return n.dot(p) - c; }
};

OrientedLine Orient(const HesseLine& line, std::span<const RangePoint> points,
                    const std::vector<int>& indices) {
  OrientedLine out{line.Normal(), line.rho_m};
  double along_rays = 0.0;
  for (int i : indices) along_rays += out.n.dot(points[i].ray_direction);
  if (along_rays < 0.0) {
    out.n = -out.n;
    out.c = -out.c;
  }
  return out;
}

std::vector<int> Band(const OrientedLine& line, std::span<const RangePoint> points,
                      const std::vector<int>& candidates, double half_width_m) {
  std::vector<int> out;
  for (int i : candidates) {
    if (std::abs(line.Distance(points[i].point_m)) <= half_width_m) out.push_back(i);
  }
  return out;
}

std::vector<RangePoint> Gather(std::span<const RangePoint> points, const std::vector<int>& idx) {
  std::vector<RangePoint> out;
  out.reserve(idx.size());
  for (int i : idx) out.push_back(points[i]);
  return out;
}

// Sorted coordinates of the points along the line's direction.
std::vector<double> Along(const Eigen::Vector2d& n, std::span<const RangePoint> points,
                          const std::vector<int>& idx) {
  const Eigen::Vector2d d(-n.y(), n.x());
  std::vector<double> s;
  s.reserve(idx.size());
  for (int i : idx) s.push_back(d.dot(points[i].point_m));
  std::sort(s.begin(), s.end());
  return s;
}

bool Supported(const std::vector<double>& along, const WallLineOptions& o) {
  if (static_cast<int>(along.size()) < o.min_inliers) return false;
  if (along.back() - along.front() < o.min_length_m) return false;
  for (std::size_t k = 1; k < along.size(); ++k) {
    if (along[k] - along[k - 1] > o.max_gap_m) return false;
  }
  return true;
}

// The band split where consecutive points along the line are more than
// max_gap_m apart (a doorway, the long shadow of a pedestrian near the
// sensor): its run with the most points.
std::vector<int> LargestRun(const Eigen::Vector2d& n, std::span<const RangePoint> points,
                            const std::vector<int>& band, double max_gap_m) {
  const Eigen::Vector2d d(-n.y(), n.x());
  std::vector<std::pair<double, int>> along;
  for (int i : band) along.emplace_back(d.dot(points[i].point_m), i);
  std::sort(along.begin(), along.end());
  std::size_t best_begin = 0, best_end = 0;
  for (std::size_t begin = 0; begin < along.size();) {
    std::size_t end = begin + 1;
    while (end < along.size() && along[end].first - along[end - 1].first <= max_gap_m) ++end;
    if (end - begin > best_end - best_begin) {
      best_begin = begin;
      best_end = end;
    }
    begin = end;
  }
  std::vector<int> run;
  for (std::size_t k = best_begin; k < best_end; ++k) run.push_back(along[k].second);
  return run;
}

bool FaceSupported(const std::vector<double>& along, const WallLineOptions& o) {
  return static_cast<int>(along.size()) >= o.min_face_inliers &&
         along.back() - along.front() >= o.min_face_span_m;
}

double PerpendicularSigma(const Eigen::Vector2d& n, const RangePoint& p, const WallLineOptions& o) {
  const double u = n.dot(p.ray_direction);
  return std::sqrt(o.range_sigma_m * o.range_sigma_m * u * u + o.face_sigma_m * o.face_sigma_m);
}

// Symmetric gating about c, iterated (header, step 4a): c <- the weighted
// mean of the s_j with |s_j - c| <= gate_sigma sigma_j.
// Returns the gated points (indices into s) at the fixed point.
std::vector<std::size_t> GateSymmetric(const std::vector<double>& s,
                                       const std::vector<double>& sigma, const WallLineOptions& o,
                                       double* c) {
  std::vector<std::size_t> gated;
  for (int it = 0; it < 20; ++it) {
    gated.clear();
    double sw = 0.0, sws = 0.0;
    for (std::size_t j = 0; j < s.size(); ++j) {
      if (std::abs(s[j] - *c) > o.gate_sigma * sigma[j]) continue;
      gated.push_back(j);
      sw += 1.0 / (sigma[j] * sigma[j]);
      sws += s[j] / (sigma[j] * sigma[j]);
    }
    if (gated.empty()) return gated;
    const double next = sws / sw;
    const bool converged = std::abs(next - *c) < 1e-5;
    *c = next;
    if (converged) break;
  }
  return gated;
}

// The weighted median of s (weights 1 / sigma^2).
double WeightedMedian(const std::vector<double>& s, const std::vector<double>& sigma) {
  std::vector<std::pair<double, double>> sw;
  double total = 0.0;
  for (std::size_t j = 0; j < s.size(); ++j) {
    sw.emplace_back(s[j], 1.0 / (sigma[j] * sigma[j]));
    total += sw.back().second;
  }
  std::sort(sw.begin(), sw.end());
  double sum = 0.0;
  for (const auto& [value, weight] : sw) {
    sum += weight;
    if (sum >= 0.5 * total) return value;
  }
  return sw.back().first;
}

struct FaceOffset {
  std::vector<int> points;  // the face's, indices into the scan
  double offset_m = 0.0;    // along the oriented line's normal
  double variance_m2 = 0.0;
  bool recessed = false;
};

// The face's offset along the fitted direction (1-D); see the header, step 4.
FaceOffset FaceAlong(const OrientedLine& line, std::span<const RangePoint> points,
                     const std::vector<int>& band, const WallLineOptions& o) {
  std::vector<double> s, sigma;
  for (int i : band) {
    s.push_back(line.Distance(points[i].point_m));
    sigma.push_back(PerpendicularSigma(line.n, points[i], o));
  }
  if (static_cast<int>(s.size()) <= o.front_rank) return {};
  // 4a: the band's centre, symmetric gating from its weighted median.
  double c = WeightedMedian(s, sigma);
  std::vector<std::size_t> gated = GateSymmetric(s, sigma, o, &c);
  // 4b: points clearly off it on either side: uprights in front of the
  // loads it settled on, or loads behind the uprights.
  int off_front = 0, off_behind = 0;
  for (std::size_t j = 0; j < s.size(); ++j) {
    off_front += c - s[j] > o.recess_sigma * sigma[j];
    off_behind += s[j] - c > o.recess_sigma * sigma[j];
  }
  FaceOffset face;
  face.recessed = std::max(off_front, off_behind) >= o.recess_min_points ||
                  static_cast<double>(gated.size()) < o.centre_min_fraction * s.size();
  if (face.recessed) {
    // 4c: the front of the band.
    std::vector<double> bound;
    for (std::size_t j = 0; j < s.size(); ++j) bound.push_back(s[j] + o.front_sigma * sigma[j]);
    std::nth_element(bound.begin(), bound.begin() + o.front_rank, bound.end());
    const double c_front = bound[o.front_rank];
    gated.clear();
    for (std::size_t j = 0; j < s.size(); ++j) {
      if (s[j] - o.front_sigma * sigma[j] <= c_front) gated.push_back(j);
    }
  }
  if (gated.empty()) return face;
  double sum_w = 0.0, sum_ws = 0.0;
  for (std::size_t j : gated) {
    face.points.push_back(band[j]);
    sum_w += 1.0 / (sigma[j] * sigma[j]);
    sum_ws += s[j] / (sigma[j] * sigma[j]);
  }
  face.offset_m = sum_ws / sum_w;
  face.variance_m2 = 1.0 / sum_w;
  return face;
}

// A recessed band's front points run along the band's direction (uprights
// all along a rack face); a band over two faces at different offsets (a dock
// wall and its doors behind) fits a direction between them, which its front
// points, the nearer face's, do not follow (header, step 4c).
bool FrontAlignedWithBand(std::span<const RangePoint> points, const std::vector<int>& front,
                          const WallLineFit& band_fit, const WallLineOptions& o) {
  const core::Result<WallLineFit> front_fit =
      FitWallLine(Gather(points, front), o.range_sigma_m, o.face_sigma_m);
  if (!front_fit.ok()) return false;
  const double tilt_rad = std::abs(
      std::remainder(front_fit->line.alpha_rad - band_fit.line.alpha_rad, std::numbers::pi));
  const double sigma_rad =
      std::sqrt(front_fit->covariance(1, 1) + band_fit.covariance(1, 1)) + o.front_tilt_slack_rad;
  return tilt_rad <= o.front_tilt_sigma * sigma_rad;
}

// RANSAC: the line through two points with the most band inliers.
std::optional<OrientedLine> BestHypothesis(std::span<const RangePoint> points,
                                           const std::vector<int>& active, const WallLineOptions& o,
                                           std::mt19937* rng) {
  if (static_cast<int>(active.size()) < o.min_inliers) return std::nullopt;
  std::uniform_int_distribution<std::size_t> pick(0, active.size() - 1);
  std::optional<OrientedLine> best;
  std::size_t best_count = 0;
  for (int it = 0; it < o.ransac_iterations; ++it) {
    const Eigen::Vector2d& a = points[active[pick(*rng)]].point_m;
    const Eigen::Vector2d& b = points[active[pick(*rng)]].point_m;
    if ((a - b).norm() < 0.5 * o.min_length_m) continue;
    const core::Result<HesseLine> line = perception::LineFromPoints(a, b);
    if (!line.ok()) continue;
    const OrientedLine hypothesis{line->Normal(), line->rho_m};
    std::size_t count = 0;
    for (int i : active) count += std::abs(hypothesis.Distance(points[i].point_m)) <= o.band_m;
    if (count > best_count) {
      best_count = count;
      best = hypothesis;
    }
  }
  if (static_cast<int>(best_count) < o.min_inliers) return std::nullopt;
  return best;
}

}  // namespace

core::Status WallLineOptions::Validate() const {
  for (const auto& [field, value] :
       {std::pair("range_sigma_m", range_sigma_m), std::pair("min_range_m", min_range_m),
        std::pair("max_range_m", max_range_m), std::pair("band_m", band_m),
        std::pair("front_sigma", front_sigma), std::pair("gate_sigma", gate_sigma),
        std::pair("recess_sigma", recess_sigma),
        std::pair("centre_min_fraction", centre_min_fraction),
        std::pair("front_tilt_sigma", front_tilt_sigma), std::pair("min_length_m", min_length_m),
        std::pair("max_gap_m", max_gap_m), std::pair("face_rho_sigma_m", face_rho_sigma_m),
        std::pair("recessed_rho_sigma_m", recessed_rho_sigma_m),
        std::pair("face_alpha_sigma_rad", face_alpha_sigma_rad),
        std::pair("front_tilt_slack_rad", front_tilt_slack_rad)}) {
    if (core::Status s = Positive(field, value); !s.ok()) return s;
  }
  if (!(face_sigma_m >= 0.0))
    return core::Status::Error("WallLineOptions.face_sigma_m: expected >= 0");
  if (!(max_range_m > min_range_m)) {
    return core::Status::Error("WallLineOptions: expected max_range_m > min_range_m");
  }
  if (front_rank < 0) {
    return core::Status::Error("WallLineOptions.front_rank: expected >= 0");
  }
  if (recess_min_points < 1) {
    return core::Status::Error("WallLineOptions.recess_min_points: expected >= 1");
  }
  if (min_inliers < 3 || min_face_inliers < 3 || ransac_iterations < 1 || max_lines < 0) {
    return core::Status::Error(
        "WallLineOptions: expected min_inliers >= 3, min_face_inliers >= 3, "
        "ransac_iterations >= 1, max_lines >= 0");
  }
  if (!(min_face_span_m > 0.0)) {
    return core::Status::Error("WallLineOptions.min_face_span_m: expected a value > 0");
  }
  return core::Status::Ok();
}

std::vector<WallLine> ExtractWallLines(std::span<const RangePoint> points,
                                       const WallLineOptions& o) {
  assert(o.Validate().ok());
  std::mt19937 rng(o.seed);
  std::vector<int> active(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) active[i] = static_cast<int>(i);
  std::vector<WallLine> walls;
  for (int attempt = 0; attempt < 2 * o.max_lines && static_cast<int>(walls.size()) < o.max_lines;
       ++attempt) {
    const std::optional<OrientedLine> hypothesis = BestHypothesis(points, active, o, &rng);
    if (!hypothesis) break;
    // Straighten the hypothesis on its whole band (faces and recessed loads).
    OrientedLine line = *hypothesis;
    std::vector<int> band = Band(line, points, active, o.band_m);
    for (int round = 0; round < 2; ++round) {
      core::Result<perception::LineFit> fit = perception::FitLineTls(
          [&] {
            std::vector<Eigen::Vector2d> xy;
            for (int i : band) xy.push_back(points[i].point_m);
            return xy;
          }(),
          {}, 1.0);
      if (!fit.ok()) break;
      line = Orient(fit->line, points, band);
      band = Band(line, points, active, o.band_m);
    }
    const auto remove_band = [&] {
      std::vector<int> kept;
      for (int i : active) {
        if (std::abs(line.Distance(points[i].point_m)) > o.band_m) kept.push_back(i);
      }
      active.swap(kept);
    };
    band = LargestRun(line.n, points, band, o.max_gap_m);
    if (!Supported(Along(line.n, points, band), o)) {
      remove_band();
      continue;
    }
    // The direction from the whole band (faces and loads are parallel), the
    // offset from its front points: the weighted mean of their distances.
    const core::Result<WallLineFit> band_fit =
        FitWallLine(Gather(points, band), o.range_sigma_m, o.face_sigma_m);
    if (!band_fit.ok()) {
      remove_band();
      continue;
    }
    line = Orient(band_fit->line, points, band);
    const FaceOffset face = FaceAlong(line, points, band, o);
    if (!FaceSupported(Along(line.n, points, face.points), o)) {
      remove_band();
      continue;
    }
    if (face.recessed && !FrontAlignedWithBand(points, face.points, *band_fit, o)) {
      remove_band();
      continue;
    }
    const double offset_m = face.offset_m;
    WallLine wall;
    wall.fit = *band_fit;
    // Moving along the oriented normal n by offset: rho changes by offset
    // times the sign of n against the normalized normal.
    const double sign = line.n.dot(band_fit->line.Normal()) > 0.0 ? 1.0 : -1.0;
    wall.fit.line =
        perception::NormalizeLine(band_fit->line.rho_m + sign * offset_m, band_fit->line.alpha_rad);
    wall.covariance = band_fit->covariance;
    const double floor_m = face.recessed ? o.recessed_rho_sigma_m : o.face_rho_sigma_m;
    wall.covariance(0, 0) += face.variance_m2 + floor_m * floor_m;
    wall.covariance(1, 1) += o.face_alpha_sigma_rad * o.face_alpha_sigma_rad;
    const Eigen::Vector2d n = wall.fit.line.Normal();
    const Eigen::Vector2d d = wall.fit.line.Direction();
    const std::vector<double> along = Along(n, points, band);
    wall.endpoint_a_m = wall.fit.line.rho_m * n + along.front() * d;
    wall.endpoint_b_m = wall.fit.line.rho_m * n + along.back() * d;
    wall.num_inliers = static_cast<int>(face.points.size());
    wall.recessed = face.recessed;
    walls.push_back(wall);
    remove_band();
  }
  std::sort(walls.begin(), walls.end(), [](const WallLine& a, const WallLine& b) {
    return (a.endpoint_b_m - a.endpoint_a_m).squaredNorm() >
           (b.endpoint_b_m - b.endpoint_a_m).squaredNorm();
  });
  return walls;
}

std::vector<LineObservation> WallLineObservations(const std::vector<WallLine>& walls) {
  std::vector<LineObservation> out;
  for (const WallLine& w : walls) {
    LineObservation o;
    o.line_base = w.fit.line;
    o.covariance = w.covariance;
    o.kind = w.recessed ? core::MarkingKind::kRackFace : core::MarkingKind::kWall;
    o.endpoint_a_base_m = w.endpoint_a_m;
    o.endpoint_b_base_m = w.endpoint_b_m;
    out.push_back(o);
  }
  return out;
}

}  // namespace groundline::localization::lidar
