#include "localize_relocalize.h"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "groundline/core/trajectory_association.h"
#include "groundline/localization/odometry_integrator.h"
#include "progress.h"

namespace groundline::tools {

std::optional<localization::ConvertedObservations> ObservationsOfImage(
    const std::filesystem::path& image, double stamp_s, const perception::BevRemap& remap,
    const perception::LineExtractor& extractor) {
  const cv::Mat grey = cv::imread(image.string(), cv::IMREAD_GRAYSCALE);
  if (grey.empty()) {
    std::fprintf(stderr, "\ngroundline localize: %s: unreadable image, frame dropped\n",
                 image.string().c_str());
    return std::nullopt;
  }
  cv::Mat bev;
  remap.Apply(grey, &bev);
  return localization::ObservationsFromExtraction(stamp_s, extractor.Extract(bev));
}

core::Result<RelocalizedStart> RelocalizeOnAtlas(
    const core::Dataset& dataset, const std::filesystem::path& image_dir,
    const perception::BevRemap& remap, const perception::LineExtractor& extractor,
    const localization::DiffDriveParams& drive, const localization::OdometryNoiseParams& noise,
    const localization::Atlas& atlas, const localization::RelocalizerOptions& options) {
  localization::Relocalizer relocalizer(atlas, options);
  localization::OdometryIntegrator integrator(drive, noise);
  const std::vector<core::ImageRecord>& images = dataset.images;
  const std::vector<core::WheelEncoderReading>& readings = dataset.wheel_encoders;
  RelocalizedStart start;
  std::size_t next_image = 0;
  ProgressLine progress("[relocalize]");
  for (std::size_t i = 0; i < readings.size(); ++i) {
    const core::WheelEncoderReading& r = readings[i];
    if (i > 0) {
      integrator.Integrate(localization::WheelAngleIncrement{r.left_delta_rad, r.right_delta_rad});
    }
    std::optional<std::size_t> frame;
    while (next_image < images.size() && images[next_image].stamp_s <= r.stamp_s + 1e-9) {
      frame = next_image++;
    }
    if (!frame) continue;
    if (i % 200 == 0) progress.Update("search", static_cast<double>(i) / readings.size());
    const localization::RelativeMotion motion = integrator.StartKeyframe();
    start.travel_m += motion.path_length_m;
    ++start.frames;
    const std::optional<localization::ConvertedObservations> seen =
        ObservationsOfImage(image_dir / images[*frame].file, r.stamp_s, remap, extractor);
    const std::optional<localization::PoseEstimate> pose = relocalizer.AddFrame(
        r.stamp_s, motion,
        seen ? seen->observations : localization::FloorObservations{r.stamp_s, {}, {}});
    if (pose) {
      progress.Update("search", 1.0);
      start.pose = *pose;
      start.status = relocalizer.status();
      return start;
    }
  }
  progress.Update("search", 1.0);
  const localization::RelocalizerStatus& s = relocalizer.status();
  return core::Status::Error(
      "--relocalize: no unambiguous pose on the atlas after " + std::to_string(start.frames) +
      " frames (" + std::to_string(static_cast<int>(start.travel_m)) +
      " m): " + std::to_string(s.hypotheses) + " hypotheses left from " + std::to_string(s.seeds) +
      " junction sightings; a repeating floor needs --near X_M Y_M [RADIUS_M] (where the drive "
      "starts), or give --initial-pose");
}

nlohmann::ordered_json RelocalizationSummary(const RelocalizedStart& start,
                                             const core::Trajectory& ground_truth) {
  constexpr double kDeg = 180.0 / std::numbers::pi;
  const core::SE2& T = start.pose.T_map_base;
  nlohmann::ordered_json j;
  j["stamp_s"] = start.pose.stamp_s;
  j["x_m"] = T.x();
  j["y_m"] = T.y();
  j["yaw_deg"] = T.yaw() * kDeg;
  j["sigma_xy_m"] = std::sqrt(0.5 * (start.pose.covariance(0, 0) + start.pose.covariance(1, 1)));
  j["travel_m"] = start.travel_m;
  j["frames"] = start.frames;
  j["junction_sightings"] = start.status.seeds;
  if (ground_truth.empty()) return j;
  core::AssociationOptions options;
  options.method = core::AssociationMethod::kInterpolate;
  options.max_dt_s = 0.05;
  const core::Result<core::Association> matched =
      core::AssociateByStamp({{start.pose.stamp_s, T, std::nullopt}}, ground_truth, options);
  if (!matched.ok() || matched->pairs.empty()) return j;
  const core::PosePair& pair = matched->pairs.front();
  j["error_m"] = (pair.T_map_est.translation() - pair.T_map_ref.translation()).norm();
  j["error_deg"] = std::abs(core::WrapAngle(pair.T_map_est.yaw() - pair.T_map_ref.yaw())) * kDeg;
  return j;
}

}  // namespace groundline::tools
