#include "groundline/perception/mount_parallel_check.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace groundline::perception {
namespace {

// Every image's lines and BEV under one mount.
struct Extraction {
  std::vector<calibration::ParallelImage> lines;
  std::vector<cv::Mat> bevs;
};

Extraction ExtractAll(const std::vector<NamedImage>& images,
                      const calibration::CameraModel& camera,
                      const calibration::CameraMount& mount, const MountParallelCheckOptions& o) {
  const BevRemap remap(camera, mount, o.bev);
  const LineExtractor extractor(remap, o.extractor);
  Extraction out;
  for (const NamedImage& image : images) {
    cv::Mat bev;
    remap.Apply(image.grey, &bev);
    calibration::ParallelImage lines;
    lines.name = image.name;
    lines.mount_used = mount;
    for (const ExtractedLine& l : extractor.Extract(bev).lines)
      lines.segments.push_back({l.start_m, l.end_m, l.covariance, std::nullopt});
    out.lines.push_back(std::move(lines));
    out.bevs.push_back(std::move(bev));
  }
  return out;
}

// The iteration has settled when pitch and roll move less than this.
constexpr double kSettledRad = 0.01 * std::numbers::pi / 180.0;

double PitchRollChange(const calibration::CameraMount& a, const calibration::CameraMount& b) {
  return std::max(std::abs(a.pitch_rad - b.pitch_rad), std::abs(a.roll_rad - b.roll_rad));
}

}  // namespace

MountParallelCheckOptions MountParallelCheckOptions::ForHeight(double height_m) {
  MountParallelCheckOptions o;
  const double scale = height_m / calibration::CameraMount{}.height_m;
  BevGridOptions& g = o.bev.grid;
  g.x_min_m *= scale;
  g.x_max_m *= scale;
  g.y_min_m *= scale;
  g.y_max_m *= scale;
  g.cell_m *= scale;
  o.extractor.min_line_length_m *= scale;
  o.extractor.bar_min_width_m *= scale;
  o.extractor.bar_max_width_m *= scale;
  o.extractor.dark = false;
  return o;
}

core::Status MountParallelCheckOptions::Validate() const {
  if (core::Status s = bev.Validate(); !s.ok()) return core::Status::Error("bev: " + s.message());
  if (core::Status s = extractor.Validate(); !s.ok())
    return core::Status::Error("extractor: " + s.message());
  if (core::Status s = solve.Validate(); !s.ok())
    return core::Status::Error("solve: " + s.message());
  if (extraction_rounds < 1) return core::Status::Error("extraction_rounds: expected >= 1");
  if (max_step_halvings < 0) return core::Status::Error("max_step_halvings: expected >= 0");
  return core::Status::Ok();
}

core::Result<MountParallelCheck> CheckMountByParallels(const std::vector<NamedImage>& images,
                                                       const calibration::CameraModel& camera,
                                                       const calibration::CameraMount& start,
                                                       const MountParallelCheckOptions& o) {
  if (core::Status s = o.Validate(); !s.ok()) return core::Status::Error(s.message());
  if (core::Status s = start.Validate(); !s.ok())
    return core::Status::Error("the start mount: " + s.message());
  if (images.empty()) return core::Status::Error("no image");
  for (const NamedImage& image : images) {
    if (image.grey.type() != CV_8UC1 || image.grey.cols != camera.width_px() ||
        image.grey.rows != camera.height_px())
      return core::Status::Error(image.name + ": expected a grey " +
                                 std::to_string(camera.width_px()) + "x" +
                                 std::to_string(camera.height_px()) +
                                 " image (the camera's), got " + std::to_string(image.grey.cols) +
                                 "x" + std::to_string(image.grey.rows));
  }
  MountParallelCheck out;
  Extraction before = ExtractAll(images, camera, start, o);
  out.lines_before = std::move(before.lines);
  out.bev_before = std::move(before.bevs);
  // Under a wrong mount the extractor may find other lines than under the
  // right one (a dashed line's dashes shrink below the least length), so
  // each solution is extracted again and solved from, until the pitch and
  // roll move by less than a hundredth of a degree. Where the extraction
  // under a solution shows no pair of lines, the step is halved back
  // towards the mount it was solved from (a solution from a poor pair can
  // land where the extractor loses a marking).
  out.lines_after = out.lines_before;
  out.bev_after = out.bev_before;
  calibration::CameraMount mount = start;
  for (int round = 0; round < o.extraction_rounds; ++round) {
    ++out.extraction_rounds;
    core::Result<calibration::MountFromParallels> solved =
        calibration::SolveMountFromParallels(out.lines_after, mount, o.solve);
    if (!solved.ok()) {
      if (round == 0) return core::Status::Error(solved.message());
      break;  // the last solution stands
    }
    out.solution = std::move(*solved);
    calibration::CameraMount candidate = out.solution.mount;
    Extraction extracted;
    bool paired = false;
    for (int halving = 0; halving <= o.max_step_halvings && !paired; ++halving) {
      if (halving > 0) {
        candidate.pitch_rad = 0.5 * (candidate.pitch_rad + mount.pitch_rad);
        candidate.roll_rad = 0.5 * (candidate.roll_rad + mount.roll_rad);
      }
      extracted = ExtractAll(images, camera, candidate, o);
      paired = !calibration::PairParallelLines(extracted.lines, candidate, o.solve).empty();
    }
    if (!paired) break;
    const double moved = PitchRollChange(candidate, mount);
    mount = candidate;
    out.lines_after = std::move(extracted.lines);
    out.bev_after = std::move(extracted.bevs);
    if (moved < kSettledRad) break;
  }
  out.measured_mount = mount;
  out.settled = PitchRollChange(out.solution.mount, mount) < kSettledRad;
  out.measured_before = calibration::PairParallelLines(out.lines_before, start, o.solve);
  out.measured_after = calibration::PairParallelLines(out.lines_after, mount, o.solve);
  return out;
}

}  // namespace groundline::perception
