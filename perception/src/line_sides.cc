// Side contrast and wide-bar edge pairing (line_sides.h).
#include "line_sides.h"
#include "groundline/core/statistics.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "groundline/perception/ridge_refinement.h"

namespace groundline::perception::internal {

namespace {

// The BEV's grey level (CV_32FC1, bilinear) at a floor point, base_link
// metres; 0 where the camera does not see.
float SampleFloor(const cv::Mat& bev_float, const BevGrid& grid, const Eigen::Vector2d& p_m) {
  const Eigen::Vector2d cell = grid.CellOfFloorPoint(p_m);
  return SampleBilinear(bev_float, cell.x(), cell.y());
}

}  // namespace

void MeasureSideContrast(const cv::Mat& bev_float, const BevGrid& grid, double offset_m,
                         double near_offset_m, double min_local_contrast,
                         CandidateLine* candidate) {
  const Eigen::Vector2d n = candidate->line.line.Normal();
  double centre = 0.0, plus = 0.0, minus = 0.0;
  int count = 0;
  auto sample = [&](const Eigen::Vector2d& p) { return SampleFloor(bev_float, grid, p); };
  for (size_t i = 0; i < candidate->centres_m.size(); i += 2) {
    const Eigen::Vector2d& p = candidate->centres_m[i];
    const float c = sample(p), a = sample(p + offset_m * n), b = sample(p - offset_m * n);
    // 0: a cell the camera does not see (a BEV made without BevRemap's fill_unseen).
    if (c == 0.0f || a == 0.0f || b == 0.0f) continue;
    centre += c;
    plus += a;
    minus += b;
    ++count;
  }
  if (count == 0) return;
  // Narrow: the profile is back halfway to each side's level near_offset_m out.
  const double sign = candidate->line.kind.polarity == LinePolarity::kBright ? 1.0 : -1.0;
  int narrow = 0, tried = 0;
  for (const Eigen::Vector2d& p : candidate->centres_m) {
    const float c = sample(p), a = sample(p + offset_m * n), b = sample(p - offset_m * n);
    const float near_a = sample(p + near_offset_m * n), near_b = sample(p - near_offset_m * n);
    if (c == 0.0f || a == 0.0f || b == 0.0f || near_a == 0.0f || near_b == 0.0f) continue;
    ++tried;
    const double depth_a = sign * (c - a), depth_b = sign * (c - b);
    const double recovered_a = sign * (near_a - c), recovered_b = sign * (near_b - c);
    // recovered: how far the grey level has come back toward the side (>= 0).
    if (std::min(depth_a, depth_b) >= min_local_contrast && -recovered_a >= 0.5 * depth_a &&
        -recovered_b >= 0.5 * depth_b) {
      ++narrow;
    }
  }
  candidate->narrow_share = tried > 0 ? static_cast<double>(narrow) / tried : 0.0;
  candidate->contrast_plus = (centre - plus) / count;
  candidate->contrast_minus = (centre - minus) / count;
  candidate->centre_grey = centre / count;
}

Sagitta MeasureSagitta(const HesseLine& line, const std::vector<Eigen::Vector2d>& points_m,
                       double correlation_samples) {
  Sagitta result;
  if (points_m.size() < 4) return result;
  const Eigen::Vector2d d = line.Direction();
  double lo = d.dot(points_m.front()), hi = lo;
  for (const Eigen::Vector2d& p : points_m) {
    lo = std::min(lo, d.dot(p));
    hi = std::max(hi, d.dot(p));
  }
  const double mid = 0.5 * (lo + hi);
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (const Eigen::Vector2d& p : points_m) {
    const double t = d.dot(p) - mid;
    const Eigen::Vector3d phi(1.0, t, t * t);
    A += phi * phi.transpose();
    b += phi * SignedDistance(line, p);
  }
  const Eigen::LDLT<Eigen::Matrix3d> ldlt = A.ldlt();
  const Eigen::Vector3d q = ldlt.solve(b);
  double ss = 0.0;
  for (const Eigen::Vector2d& p : points_m) {
    const double t = d.dot(p) - mid;
    const double r = SignedDistance(line, p) - (q(0) + q(1) * t + q(2) * t * t);
    ss += r * r;
  }
  const double n = static_cast<double>(points_m.size());
  // Residual variance per centre; neighbouring centres share their smoothing,
  // so the curvature's variance grows by the correlation length in samples.
  const double var = ss / (n - 3.0) * std::max(1.0, correlation_samples);
  const double var_c = var * ldlt.solve(Eigen::Vector3d::UnitZ())(2);
  const double quarter_span2 = 0.25 * (hi - lo) * (hi - lo);
  result.sagitta_m = std::abs(q(2)) * quarter_span2;
  result.sigma_m = std::sqrt(std::max(0.0, var_c)) * quarter_span2;
  result.span_m = hi - lo;
  return result;
}

double MedianGrey(const cv::Mat& bev, const cv::Mat& mask) {
  int histogram[256] = {};
  int total = 0;
  for (int r = 0; r < bev.rows; ++r) {
    const std::uint8_t* b = bev.ptr<std::uint8_t>(r);
    const std::uint8_t* m = mask.ptr<std::uint8_t>(r);
    for (int c = 0; c < bev.cols; ++c) {
      if (m[c] == 0) continue;
      ++histogram[b[c]];
      ++total;
    }
  }
  int below = 0;
  for (int g = 0; g < 256; ++g) {
    below += histogram[g];
    if (2 * below >= total) return g;
  }
  return 0.0;
}

// Projections of both lines' endpoints onto `line` span the merged segment.
void SpanEndpoints(const ExtractedLine& a, const ExtractedLine& b, ExtractedLine* merged) {
  const Eigen::Vector2d d = merged->line.Direction();
  const Eigen::Vector2d foot = merged->line.rho_m * merged->line.Normal();
  double lo = d.dot(a.start_m), hi = lo;
  for (const Eigen::Vector2d& p : {a.start_m, a.end_m, b.start_m, b.end_m}) {
    lo = std::min(lo, d.dot(p));
    hi = std::max(hi, d.dot(p));
  }
  merged->start_m = foot + lo * d;
  merged->end_m = foot + hi * d;
}

double Overlap(const ExtractedLine& a, const ExtractedLine& b) {
  const Eigen::Vector2d d = a.line.Direction();
  const double a0 = std::min(d.dot(a.start_m), d.dot(a.end_m));
  const double a1 = std::max(d.dot(a.start_m), d.dot(a.end_m));
  const double b0 = std::min(d.dot(b.start_m), d.dot(b.end_m));
  const double b1 = std::max(d.dot(b.start_m), d.dot(b.end_m));
  return std::min(a1, b1) - std::max(a0, b0);
}

namespace {

// A dark line significantly curved, and more than a saw cut's residual bend
// (the lens model's error bends a straight joint into an arc of tens of
// metres): a tire's scuff, an arc of a few metres.
bool IsArc(const Sagitta& sagitta, const LineExtractorOptions& options) {
  if (!(sagitta.sagitta_m > options.dark_min_significant_sagitta_m &&
        sagitta.sagitta_m > options.dark_sagitta_significance * sagitta.sigma_m)) {
    return false;
  }
  const double radius = sagitta.span_m * sagitta.span_m / (8.0 * sagitta.sagitta_m);
  return radius < options.dark_arc_max_radius_m;
}

// The largest mean contrast (centre minus side, grey levels) of a bright
// candidate against the side along sign * normal, over offsets of 1 ..
// max_cells cells.
double MaxSideContrast(const cv::Mat& bev_float, const BevGrid& grid, const CandidateLine& candidate,
                       double sign, double max_cells) {
  const Eigen::Vector2d n = sign * grid.cell_m() * candidate.line.line.Normal();
  std::vector<float> centres;  // every other centre's grey, as MeasureSideContrast samples
  for (size_t i = 0; i < candidate.centres_m.size(); i += 2) {
    centres.push_back(SampleFloor(bev_float, grid, candidate.centres_m[i]));
  }
  double best = -std::numeric_limits<double>::infinity();
  for (int k = 1; k <= static_cast<int>(max_cells); ++k) {
    double sum = 0.0;
    int count = 0;
    for (size_t j = 0; j < centres.size(); ++j) {
      const float side = SampleFloor(bev_float, grid, candidate.centres_m[2 * j] + k * n);
      if (centres[j] == 0.0f || side == 0.0f) continue;  // unseen
      sum += centres[j] - side;
      ++count;
    }
    if (count > 0) best = std::max(best, sum / count);
  }
  return best;
}

// A short dark piece is believed only when its centres line up as a saw
// cut's do: a scuff's or a stain's edge is ragged.
bool IsRaggedShortDark(const ExtractedLine& line, const LineExtractorOptions& options) {
  return (line.end_m - line.start_m).norm() < options.dark_short_length_m &&
         line.rms_residual_m > options.dark_short_max_rms_m;
}

}  // namespace

void SelectLines(std::vector<CandidateLine> candidates, LinePolarity polarity,
                 double floor_median_grey, const cv::Mat& bev_float, const BevGrid& grid,
                 const LineExtractorOptions& options, std::vector<ExtractedLine>* out,
                 std::vector<CandidateLine>* unpaired_edges) {
  const double sign = polarity == LinePolarity::kBright ? 1.0 : -1.0;
  const double min_contrast = polarity == LinePolarity::kBright ? options.min_side_contrast
                                                                : options.min_dark_side_contrast;
  std::vector<int> edges;
  for (size_t i = 0; i < candidates.size(); ++i) {
    const double plus = sign * candidates[i].contrast_plus;
    const double minus = sign * candidates[i].contrast_minus;
    // Where bright markings fill most of the view the median floor grey is
    // theirs: an edge whose dark side is less than half as bright passes too
    // (the edge of an oil stain darkens concrete by <= 40 %).
    const bool strong_edge = std::max(plus, minus) >=
                             options.single_edge_min_relative_contrast * candidates[i].centre_grey;
    if (polarity == LinePolarity::kBright && !strong_edge &&
        candidates[i].centre_grey < floor_median_grey + options.min_bright_excess) {
      continue;
    }
    if (polarity == LinePolarity::kDark &&
        (candidates[i].narrow_share < options.min_dark_narrow_share ||
         candidates[i].sagitta.sagitta_m > options.max_dark_sagitta_m ||
         IsArc(candidates[i].sagitta, options) || IsRaggedShortDark(candidates[i].line, options))) {
      continue;
    }
    const auto sharp = [&](bool both_sides) {
      if (polarity != LinePolarity::kBright || options.min_flank_sharpness <= 0.0) return true;
      const double s = MeasureFlankSharpness(bev_float, grid, candidates[i], both_sides,
                                             options.flank_max_cells, 0.5 * min_contrast);
      return !(s < options.min_flank_sharpness);  // NaN (not measured): kept
    };
    // A narrow bright line is brighter than both sides alike (tape on
    // concrete); much brighter than one side only, it is the lit flank of a
    // shadow or a stain: an edge, for the bar and single-edge tests.
    // The weaker side's contrast is its best over the offsets up to
    // side_offset (a tape split by the joint under it falls into the groove
    // 2-3 cm out, then rises onto the tape's other half).
    const auto symmetric = [&] {
      if (polarity != LinePolarity::kBright) return true;
      const double needed = options.min_bright_side_ratio * std::max(plus, minus);
      if (std::min(plus, minus) >= needed ||
          std::min(plus, minus) >= options.bright_side_min_grey_share * candidates[i].centre_grey) {
        return true;
      }
      const double weak_sign = plus < minus ? 1.0 : -1.0;  // +n when contrast_plus is weaker
      return MaxSideContrast(bev_float, grid, candidates[i], weak_sign,
                             options.side_offset_cells) >= needed;
    };
    if (std::min(plus, minus) >= min_contrast && symmetric()) {
      if (!sharp(true)) continue;
      out->push_back(candidates[i].line);
    } else if (polarity == LinePolarity::kBright && std::max(plus, minus) >= min_contrast) {
      if (!sharp(false)) continue;
      edges.push_back(static_cast<int>(i));
    }
  }
  // Facing edges: each one's bright side (the side as bright as its centre,
  // the smaller contrast) points at the other.
  std::vector<bool> used(candidates.size(), false);
  for (size_t x = 0; x < edges.size(); ++x) {
    const CandidateLine& a = candidates[edges[x]];
    int best = -1;
    double best_separation = options.bar_max_width_m;
    for (size_t y = 0; y < edges.size(); ++y) {
      if (x == y || used[edges[y]]) continue;
      const CandidateLine& b = candidates[edges[y]];
      const Eigen::Vector2d difference = LineDifference(b.line.line, a.line.line);
      if (std::abs(difference(1)) > options.bar_max_angle_rad) continue;
      const Eigen::Vector2d b_mid = 0.5 * (b.line.start_m + b.line.end_m);
      const Eigen::Vector2d a_mid = 0.5 * (a.line.start_m + a.line.end_m);
      const double a_to_b = SignedDistance(a.line.line, b_mid);
      const double b_to_a = SignedDistance(b.line.line, a_mid);
      const bool a_faces_b = (a.contrast_plus < a.contrast_minus) == (a_to_b > 0.0);
      const bool b_faces_a = (b.contrast_plus < b.contrast_minus) == (b_to_a > 0.0);
      const double separation = std::abs(a_to_b);
      if (!a_faces_b || !b_faces_a || separation < options.bar_min_width_m ||
          separation > best_separation) {
        continue;
      }
      if (Overlap(a.line, b.line) < 0.5 * std::max(a.line.LengthM(), b.line.LengthM())) continue;
      if (options.bar_min_roughness_ratio > 0.0) {
        // Inside (the bright sides) against outside, over both edges; the
        // inner band stops short of the other edge.
        const double near = options.single_edge_roughness_near_m;
        const double far = std::min(options.single_edge_roughness_far_m, separation - near);
        if (far > near) {
          // From the steps themselves (the ridge centres lie on the bar's
          // inner flanks); a pair whose steps are not found keeps the bar.
          const std::vector<Eigen::Vector2d> pa =
              LocateBarEdge(bev_float, grid, a, options.single_edge_min_contrast);
          const std::vector<Eigen::Vector2d> pb =
              LocateBarEdge(bev_float, grid, b, options.single_edge_min_contrast);
          if (pa.size() >= 3 && pb.size() >= 3) {
            const SideRoughness ra = MeasureSideRoughness(bev_float, grid, a, pa, near, far);
            const SideRoughness rb = MeasureSideRoughness(bev_float, grid, b, pb, near, far);
            const double inside = 0.5 * (ra.bright_dn + rb.bright_dn);
            const double outside = 0.5 * (ra.dark_dn + rb.dark_dn);
            if (!(outside >= options.bar_min_roughness_ratio * inside)) continue;
          }
        }
      }
      best = edges[y];
      best_separation = separation;
    }
    if (best < 0 || used[edges[x]]) continue;
    used[edges[x]] = used[best] = true;
    const ExtractedLine& la = a.line;
    const ExtractedLine& lb = candidates[best].line;
    ExtractedLine merged = la;
    // The mean of the two edges in la's description, then normalized; lb's
    // covariance is carried into la's description first.
    const Eigen::Vector2d half = 0.5 * LineDifference(lb.line, la.line);
    merged.covariance =
        0.25 * (la.covariance + CovarianceInDescriptionOf(lb.line, la.line, lb.covariance));
    merged.line =
        NormalizeLine(la.line.rho_m + half(0), la.line.alpha_rad + half(1), &merged.covariance);
    merged.from_bar_edges = true;
    merged.energy = 0.5 * (la.energy + lb.energy);
    merged.rms_residual_m = std::max(la.rms_residual_m, lb.rms_residual_m);
    merged.samples = la.samples + lb.samples;
    SpanEndpoints(la, lb, &merged);
    out->push_back(merged);
  }
  if (unpaired_edges == nullptr) return;
  for (const int e : edges) {
    if (!used[e]) unpaired_edges->push_back(std::move(candidates[e]));
  }
}

std::vector<Eigen::Vector2d> LocateBarEdge(const cv::Mat& bev_float, const BevGrid& grid,
                                           const CandidateLine& candidate, double min_step_dn) {
  constexpr int kFirst = -2, kLast = 14;     // profile, cells from the ridge centre
  constexpr int kDarkFrom = 2, kDarkTo = 6;  // cells beyond the edge that must stay dark
  constexpr int kCount = kLast - kFirst + 1;
  const Eigen::Vector2d n = candidate.line.line.Normal();
  // The dark side is the one of the larger contrast.
  const Eigen::Vector2d toward_dark =
      (candidate.contrast_plus > candidate.contrast_minus ? 1.0 : -1.0) * grid.cell_m() * n;
  std::vector<Eigen::Vector2d> edge;
  edge.reserve(candidate.centres_m.size());
  for (const Eigen::Vector2d& p : candidate.centres_m) {
    float profile[kCount];
    bool seen = true;
    for (int k = 0; k < kCount && seen; ++k) {
      const Eigen::Vector2d cell = grid.CellOfFloorPoint(p + (kFirst + k) * toward_dark);
      profile[k] = SampleBilinear(bev_float, cell.x(), cell.y());
      seen = profile[k] != 0.0f;
    }
    if (!seen) continue;
    // Central differences D(k) = I(k + 1) - I(k - 1); the most negative one.
    int best = -1;
    float best_step = 0.0f;
    for (int k = 1; k + 1 < kCount; ++k) {
      const float step = profile[k + 1] - profile[k - 1];
      if (step < best_step) {
        best_step = step;
        best = k;
      }
    }
    if (best < 2 || best + kDarkTo >= kCount || -best_step < min_step_dn) continue;
    // A step, not a groove (the flank of a joint crossing a bar): the far side
    // stays darker than halfway for several cells.
    const float halfway = profile[best - 2] + 0.5f * best_step;
    bool step = true;
    for (int k = best + kDarkFrom; k <= best + kDarkTo; ++k) step = step && profile[k] < halfway;
    if (!step) continue;
    const float dm = profile[best] - profile[best - 2];
    const float dp = profile[best + 2] - profile[best];
    const float curvature = dm - 2.0f * best_step + dp;
    const double delta = curvature > 0.0f ? 0.5 * (dm - dp) / curvature : 0.0;
    edge.push_back(p + (kFirst + best + std::clamp(delta, -0.5, 0.5)) * toward_dark);
  }
  return edge;
}

double OpenBrightSideShare(const cv::Mat& bev_float, const cv::Mat& search_mask,
                           const BevGrid& grid, const CandidateLine& candidate,
                           const std::vector<Eigen::Vector2d>& edge_points_m, double max_width_m) {
  if (edge_points_m.empty()) return 0.0;
  const Eigen::Vector2d toward_bright =
      (candidate.contrast_plus > candidate.contrast_minus ? -1.0 : 1.0) * grid.cell_m() *
      candidate.line.line.Normal();
  const double contrast = std::max(candidate.contrast_plus, candidate.contrast_minus);
  const int steps = static_cast<int>(std::ceil(max_width_m / grid.cell_m())) + 3;
  auto sample = [&](const Eigen::Vector2d& p) { return SampleFloor(bev_float, grid, p); };
  auto searched = [&](const Eigen::Vector2d& p) {
    const Eigen::Vector2d cell = grid.CellOfFloorPoint(p);
    const int c = static_cast<int>(std::lround(cell.x()));
    const int r = static_cast<int>(std::lround(cell.y()));
    return c >= 0 && r >= 0 && c < search_mask.cols && r < search_mask.rows &&
           search_mask.at<std::uint8_t>(r, c) != 0;
  };
  int open = 0;
  for (const Eigen::Vector2d& p : edge_points_m) {
    const float bright = sample(p + 3.0 * toward_bright);
    if (bright == 0.0f) continue;
    const double halfway = bright - 0.5 * contrast;
    for (int k = 4; k <= steps; ++k) {
      const Eigen::Vector2d q = p + static_cast<double>(k) * toward_bright;
      if (!searched(q)) {
        ++open;
        break;
      }
      if (sample(q) < halfway) break;
    }
  }
  return static_cast<double>(open) / static_cast<double>(edge_points_m.size());
}

SideRoughness MeasureSideRoughness(const cv::Mat& bev_float, const BevGrid& grid,
                                   const CandidateLine& candidate,
                                   const std::vector<Eigen::Vector2d>& edge_points_m, double near_m,
                                   double far_m) {
  const Eigen::Vector2d toward_bright =
      (candidate.contrast_plus > candidate.contrast_minus ? -1.0 : 1.0) *
      candidate.line.line.Normal();
  const Eigen::Vector2d along = grid.cell_m() * candidate.line.line.Direction();
  auto sample = [&](const Eigen::Vector2d& p) { return SampleFloor(bev_float, grid, p); };
  const auto side = [&](double sign) {
    std::vector<double> steps, greys;
    for (const Eigen::Vector2d& p : edge_points_m) {
      for (double o = near_m; o <= far_m + 1e-9; o += grid.cell_m()) {
        const Eigen::Vector2d q = p + sign * o * toward_bright;
        const float a = sample(q), b = sample(q + along);
        // 0: a cell the camera does not see.
        if (a == 0.0f || b == 0.0f) continue;
        steps.push_back(std::abs(a - b));
        greys.push_back(a);
      }
    }
    if (steps.empty()) return std::pair<double, double>(0.0, 0.0);
    const double grey = core::Median(greys);
    const double step = core::Median(steps);
    return std::pair<double, double>(grey > 0.0 ? step / grey : 0.0, step);
  };
  const auto [bright, bright_dn] = side(1.0);
  const auto [dark, dark_dn] = side(-1.0);
  return {bright, dark, bright_dn, dark_dn};
}

double MeasureFlankSharpness(const cv::Mat& bev_float, const BevGrid& grid,
                             const CandidateLine& candidate, bool both_sides, int max_cells,
                             double min_fall_dn) {
  const Eigen::Vector2d n = grid.cell_m() * candidate.line.line.Normal();
  // +n is darker when its contrast (centre minus side) is the larger.
  const double dark_sign = candidate.contrast_plus > candidate.contrast_minus ? 1.0 : -1.0;
  std::vector<double> ratios;
  std::vector<float> profile(static_cast<std::size_t>(max_cells) + 2);
  for (const Eigen::Vector2d& p : candidate.centres_m) {
    double ratio = std::numeric_limits<double>::infinity();
    bool measured = false, seen = true, falls = true;
    for (const double sign : {dark_sign, -dark_sign}) {
      if (sign != dark_sign && !both_sides) break;
      // profile[k]: k cells from the centre toward this side, k = 0..max + 1.
      for (int k = 0; k <= max_cells + 1 && seen; ++k) {
        const Eigen::Vector2d cell = grid.CellOfFloorPoint(p + sign * k * n);
        profile[static_cast<std::size_t>(k)] = SampleBilinear(bev_float, cell.x(), cell.y());
        seen = profile[static_cast<std::size_t>(k)] != 0.0f;
      }
      if (!seen) break;
      // The top: the brightest of the centre's cell and its two neighbours;
      // the bottom: the mean of the outer half (a joint or tape nearby moves
      // it little).
      float top = profile[0], steepest = 0.0f;
      double outer = 0.0;
      int outer_count = 0;
      for (int k = 1; k <= max_cells; ++k) {
        const auto i = static_cast<std::size_t>(k);
        if (k <= 2) top = std::max(top, profile[i]);
        if (2 * k >= max_cells) {
          outer += profile[i];
          ++outer_count;
        }
        steepest = std::max(steepest, 0.5f * (profile[i - 1] - profile[i + 1]));
      }
      const double fall = top - outer / outer_count;
      if (fall < min_fall_dn) falls = false;
      ratio = std::min(ratio, steepest / fall);
      measured = true;
    }
    if (seen && measured && falls) ratios.push_back(ratio);
  }
  return ratios.empty() ? std::numeric_limits<double>::quiet_NaN() : core::Median(ratios);
}

WidthGrowth WidthGrowthWithRange(const cv::Mat& bev_float, const BevGrid& grid,
                                 const ExtractedLine& line, const Eigen::Vector2d& foot_m,
                                 double max_half_width_m) {
  constexpr double kStepM = 0.02;
  constexpr std::size_t kMinPositions = 8;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double length = line.LengthM();
  const int cells = static_cast<int>(std::ceil(max_half_width_m / grid.cell_m()));
  if (length < kStepM || cells < 3) return {};
  const Eigen::Vector2d d = (line.end_m - line.start_m) / length;
  const Eigen::Vector2d n(-d.y(), d.x());
  // Brighter than the sides for a bright line: +1; darker: -1.
  const double sign = line.kind.polarity == LinePolarity::kDark ? -1.0 : 1.0;
  std::vector<double> ranges, widths;
  std::vector<double> profile(static_cast<std::size_t>(cells) + 1);
  for (double s = 0.0; s <= length; s += kStepM) {
    const Eigen::Vector2d p = line.start_m + s * d;
    double centre = -std::numeric_limits<double>::infinity();
    for (int k = -1; k <= 1; ++k) {
      const Eigen::Vector2d c = grid.CellOfFloorPoint(p + k * grid.cell_m() * n);
      centre = std::max(centre, sign * SampleBilinear(bev_float, c.x(), c.y()));
    }
    double half_width[2] = {nan, nan};
    bool seen = true;
    for (int side = 0; side < 2 && seen; ++side) {
      const double dir = side == 0 ? 1.0 : -1.0;
      for (int k = 0; k <= cells && seen; ++k) {
        const Eigen::Vector2d c = grid.CellOfFloorPoint(p + dir * k * grid.cell_m() * n);
        const float v = SampleBilinear(bev_float, c.x(), c.y());
        seen = v != 0.0f;  // unseen cells are 0 (BevRemap)
        profile[static_cast<std::size_t>(k)] = sign * v;
      }
      if (!seen) break;
      std::vector<double> outer(profile.begin() + 2 * cells / 3, profile.end());
      const double level = 0.5 * (centre + core::Median(outer));
      if (!(centre - level > 2.0)) continue;  // no band on this side
      for (int k = 1; k <= cells; ++k) {
        const double a = profile[static_cast<std::size_t>(k - 1)];
        const double b = profile[static_cast<std::size_t>(k)];
        if (b < level) {
          const double t = a > b ? (a - level) / (a - b) : 0.0;
          half_width[side] = (k - 1 + std::clamp(t, 0.0, 1.0)) * grid.cell_m();
          break;
        }
      }
    }
    if (!seen || !std::isfinite(half_width[0]) || !std::isfinite(half_width[1])) continue;
    ranges.push_back((p - foot_m).norm());
    widths.push_back(half_width[0] + half_width[1]);
  }
  if (ranges.size() < kMinPositions) return {};
  // Medians of the nearer and the farther half of the positions: a stain or
  // a crossing line that widens the band at a few positions moves them little.
  std::vector<std::size_t> order(ranges.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return ranges[a] < ranges[b]; });
  const std::size_t half = order.size() / 2;
  std::vector<double> r_near, w_near, r_far, w_far;
  for (std::size_t k = 0; k < order.size(); ++k) {
    (k < half ? r_near : r_far).push_back(ranges[order[k]]);
    (k < half ? w_near : w_far).push_back(widths[order[k]]);
  }
  const double rn = core::Median(r_near), rf = core::Median(r_far);
  const double wn = core::Median(w_near), wf = core::Median(w_far);
  if (rf - rn < 0.1 * rn || !(wn > 0.0)) return {};
  return {(wf / wn - 1.0) / (rf / rn - 1.0), wf - wn};
}

}  // namespace groundline::perception::internal
