// JSON and overlay output of `groundline extract` (extract_output.h).
#include "extract_output.h"

#include <Eigen/LU>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <string>

#include "groundline/core/angles.h"
#include "groundline/core/statistics.h"
#include "json_number.h"

namespace groundline::tools {
namespace {

nlohmann::ordered_json Vec(const Eigen::Vector2d& v) { return {v.x(), v.y()}; }
nlohmann::ordered_json Cov(const Eigen::Matrix2d& c) {
  return {c(0, 0), c(0, 1), c(1, 0), c(1, 1)};
}

}  // namespace

nlohmann::ordered_json FrameToJson(const std::string& image, double ms,
                                   const perception::LineExtraction& extraction) {
  nlohmann::ordered_json frame;
  frame["image"] = image;
  frame["ms"] = ms;
  nlohmann::ordered_json lines = nlohmann::ordered_json::array();
  for (const perception::ExtractedLine& l : extraction.lines) {
    nlohmann::ordered_json line;
    line["rho_m"] = l.line.rho_m;
    line["alpha_rad"] = l.line.alpha_rad;
    line["cov"] = Cov(l.covariance);
    line["kind"] = std::string(perception::LineKindName(l.kind));
    line["start_m"] = Vec(l.start_m);
    line["end_m"] = Vec(l.end_m);
    line["length_m"] = l.LengthM();
    line["bar"] = l.from_bar_edges;
    line["edge"] = l.single_bar_edge;
    line["samples"] = l.samples;
    line["rms_residual_m"] = l.rms_residual_m;
    line["noise_sigma_px"] = l.noise_sigma_px;
    lines.push_back(line);
  }
  frame["lines"] = lines;
  nlohmann::ordered_json junctions = nlohmann::ordered_json::array();
  for (const perception::Junction& j : extraction.junctions) {
    nlohmann::ordered_json junction;
    junction["point_m"] = Vec(j.point_m);
    junction["cov"] = Cov(j.covariance);
    junction["lines"] = {j.line_a, j.line_b};
    junction["shape"] = perception::JunctionShapeName(j.shape);
    junctions.push_back(junction);
  }
  frame["junctions"] = junctions;
  frame["energy_thresholds"] = {extraction.bright_threshold, extraction.dark_threshold};
  return frame;
}

nlohmann::ordered_json TruthToJson(const perception::ExtractedLine& line,
                                   const perception::TrueLine& truth) {
  const Eigen::Vector2d r = perception::LineError(line.line, truth.line);
  nlohmann::ordered_json out;
  out["marking_id"] = truth.marking_id;
  out["kind"] = std::string(core::MarkingKindName(truth.kind));
  out["edge"] = truth.edge;
  out["evaluated"] = truth.evaluated;
  out["error"] = Vec(r);
  out["nees"] = FiniteOrNull(r.dot(line.covariance.inverse() * r));
  return out;
}

nlohmann::ordered_json MissedTruthToJson(const perception::TrueLine& truth) {
  nlohmann::ordered_json out;
  out["marking_id"] = truth.marking_id;
  out["kind"] = std::string(core::MarkingKindName(truth.kind));
  out["edge"] = truth.edge;
  out["rho_m"] = truth.line.rho_m;
  out["alpha_rad"] = truth.line.alpha_rad;
  out["start_m"] = Vec(truth.start_m);
  out["end_m"] = Vec(truth.end_m);
  out["evaluated_length_m"] = truth.evaluated_length_m;
  out["longest_evaluated_run_m"] = truth.longest_evaluated_run_m;
  return out;
}

nlohmann::ordered_json MountToJson(const calibration::CameraMount& mount,
                                   const std::string& source) {
  return {{"source", source},
          {"height_m", mount.height_m},
          {"pitch_deg", mount.pitch_rad * core::kRadToDeg},
          {"roll_deg", mount.roll_rad * core::kRadToDeg},
          {"yaw_deg", mount.yaw_rad * core::kRadToDeg},
          {"forward_m", mount.forward_m},
          {"lateral_m", mount.lateral_m}};
}

nlohmann::ordered_json ErrorSummaryToJson(const perception::LineErrorSummary& s) {
  nlohmann::ordered_json out;
  out["evaluated_truths"] = s.evaluated_truths;
  out["detected_truths"] = s.detected_truths;
  out["detections"] = s.detections;
  out["false_detections"] = s.false_detections;
  out["tpr"] = FiniteOrNull(s.Tpr());
  out["fp_share"] = FiniteOrNull(s.FpShare());
  out["rho_err_median_m"] = FiniteOrNull(s.MedianAbsRhoErrorM());
  out["alpha_err_median_deg"] = FiniteOrNull(s.MedianAbsAlphaErrorRad() * 180.0 / M_PI);
  out["nees_inside_95_band_share"] = FiniteOrNull(s.NeesInsideBandShare());
  out["nees_median"] = FiniteOrNull(core::Median(s.nees));
  return out;
}

nlohmann::ordered_json NuisanceSummaryToJson(const perception::LineEvaluation& evaluation) {
  nlohmann::ordered_json out;
  for (const auto& [cls, s] : evaluation.by_nuisance()) {
    out[cls] = {{"false_lines", s.false_detections},
                {"false_share", FiniteOrNull(s.FpShare())},
                {"truths_touched", s.evaluated_truths},
                {"tpr_touched", FiniteOrNull(s.Tpr())}};
  }
  return out;
}

void PrintNuisanceTable(const perception::LineEvaluation& evaluation) {
  std::printf("  %-22s %11s %11s %15s %11s\n", "nuisance class", "false lines", "false share",
              "truths touched", "tpr there");
  for (const auto& [cls, s] : evaluation.by_nuisance()) {
    std::printf("  %-22s %11d %11.4f %15d %11s\n", cls.c_str(), s.false_detections,
                s.detections > 0 ? s.FpShare() : 0.0, s.evaluated_truths,
                s.evaluated_truths > 0 ? std::to_string(s.Tpr()).substr(0, 6).c_str() : "-");
  }
}

cv::Mat DrawOverlay(const cv::Mat& bev, const perception::BevGrid& grid,
                    const perception::LineExtraction& extraction,
                    std::span<const perception::TrueLine> truths) {
  constexpr int kScale = 3;  // upsampled so that 1 cm shows
  cv::Mat grey, colour;
  cv::resize(bev, grey, cv::Size(), kScale, kScale, cv::INTER_NEAREST);
  cv::cvtColor(grey, colour, cv::COLOR_GRAY2BGR);
  auto pixel = [&](const Eigen::Vector2d& floor) {
    const Eigen::Vector2d c = grid.CellOfFloorPoint(floor);
    return cv::Point(static_cast<int>(std::lround((c.x() + 0.5) * kScale - 0.5)),
                     static_cast<int>(std::lround((c.y() + 0.5) * kScale - 0.5)));
  };
  for (const perception::TrueLine& t : truths) {
    cv::line(colour, pixel(t.start_m), pixel(t.end_m), kTruthColour, 1, cv::LINE_AA);
  }
  for (const perception::ExtractedLine& l : extraction.lines) {
    const bool bright = l.kind.polarity == perception::LinePolarity::kBright;
    const cv::Scalar c = l.single_bar_edge ? kSingleEdgeColour
                         : bright          ? kBrightColour
                                           : kDarkColour;
    cv::line(colour, pixel(l.start_m), pixel(l.end_m), c, l.from_bar_edges ? 3 : 1, cv::LINE_AA);
  }
  for (const perception::Junction& j : extraction.junctions) {
    cv::circle(colour, pixel(j.point_m), 4 * kScale, kJunctionColour, 2, cv::LINE_AA);
  }
  return WithLegend(colour, !truths.empty());
}

cv::Mat WithLegend(const cv::Mat& overlay, bool with_truth) {
  struct Entry {
    cv::Scalar colour;
    int thickness;
    bool circle;
    const char* text;
  };
  std::vector<Entry> entries = {
      {kBrightColour, 1, false, "bright line (tape edge)"},
      {kBrightColour, 3, false, "thick: centre line of a bar (two edges)"},
      {kDarkColour, 1, false, "dark line (joint, seam)"},
      {kSingleEdgeColour, 1, false, "the one visible edge of a wide bar"},
      {kJunctionColour, 2, true, "junction"},
  };
  if (with_truth) entries.push_back({kTruthColour, 1, false, "ground truth (evaluation only)"});
  constexpr int kRowPx = 18;
  cv::Mat legend(kRowPx * static_cast<int>(entries.size()) + 6, overlay.cols, CV_8UC3,
                 cv::Scalar::all(255));
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const Entry& e = entries[i];
    const int y = 3 + kRowPx * static_cast<int>(i) + kRowPx / 2;
    if (e.circle) {
      cv::circle(legend, cv::Point(20, y), 6, e.colour, e.thickness, cv::LINE_AA);
    } else {
      cv::line(legend, cv::Point(6, y), cv::Point(34, y), e.colour, e.thickness, cv::LINE_8);
    }
    cv::putText(legend, e.text, cv::Point(42, y + 5), cv::FONT_HERSHEY_SIMPLEX, 0.42,
                cv::Scalar::all(0), 1, cv::LINE_AA);
  }
  cv::Mat out;
  cv::vconcat(overlay, legend, out);
  return out;
}

}  // namespace groundline::tools
