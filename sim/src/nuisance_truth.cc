// WriteNuisanceTruth and WriteVehicleTruth: the simulator's truth about the
// floor's nuisances and the vehicle's odometry (sim_run.h), for evaluation only.
#include <nlohmann/json.hpp>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/core/atomic_file.h"
#include "groundline/sim/floor_nuisances.h"
#include "groundline/sim/mount_perturbation.h"
#include "groundline/sim/sim_run.h"

namespace groundline::sim {

core::Status WriteNuisanceTruth(const std::filesystem::path& dir, const SimRun& run) {
  if (!run.camera) return core::Status::Ok();
  const FloorRenderOptions& o = run.camera->render;
  nlohmann::ordered_json j;
  j["format"] = "groundline-nuisance-truth";
  j["version"] = "1.0";
  j["note"] = "simulator ground truth: for evaluation only";
  // The scene's nuisance parameters (those the randomized preset draws).
  j["render"] = {
      {"texture", o.texture},
      {"texture_contrast", o.texture_contrast},
      {"scuffs", o.scuffs},
      {"scuff_darkness", o.scuff_darkness},
      {"oil", o.oil},
      {"oil_darkness", o.oil_darkness},
      {"lux", o.lux},
      {"exposure_reference_lux", o.exposure_reference_lux},
      {"gradient_fraction", o.illumination_gradient ? o.gradient_fraction : 0.0},
      {"shadows", o.shadows},
      {"shadow_factor", o.shadow_factor},
      {"shadow_cover", o.shadow_cover},
      {"glare", o.glare},
      {"glare_peak_dn", o.glare_peak_dn},
      {"glare_sigma_m", o.glare_sigma_m},
      {"glare_row_pitch_m", o.glare_row_pitch_m},
      {"glare_row_length_m", o.glare_row_length_m},
      {"cast_shadows", o.cast_shadows},
      {"cast_shadow_factor", o.cast_shadow_factor},
      {"cast_shadow_cover", o.cast_shadow_cover},
      {"shadow_penumbra_m", o.shadow_penumbra_m},
      {"vehicle_shadow", o.vehicle_shadow},
      {"vehicle_shadow_factor", o.vehicle_shadow_factor},
      {"tire_marks", o.tire_marks},
      {"tire_mark_darkness", o.tire_mark_darkness},
      {"tire_mark_density", o.tire_mark_density},
      {"patches", o.patches},
      {"patch_contrast", o.patch_contrast},
      {"patch_cover", o.patch_cover},
      {"wet", o.wet},
      {"wet_darkness", o.wet_darkness},
      {"wet_cover", o.wet_cover},
      {"standing_objects", o.occlusion && o.standing_objects},
      {"clutter_per_100m", o.clutter_per_100m},
      {"motion_blur_exposure_s", o.motion_blur ? o.exposure_s : 0.0},
      {"read_noise_dn", o.noise ? o.read_noise_dn : 0.0},
  };
  nlohmann::ordered_json segments = nlohmann::ordered_json::array();
  for (const NuisanceSegment& s :
       FloorNuisanceSegments(o, run.world.floor_min_m, run.world.floor_max_m)) {
    segments.push_back({{"class", NuisanceClassName(s.cls)},
                        {"a_m", {s.a_m.x(), s.a_m.y()}},
                        {"b_m", {s.b_m.x(), s.b_m.y()}}});
  }
  j["segments_map"] = std::move(segments);
  nlohmann::ordered_json shadows = nlohmann::ordered_json::array();
  if (o.vehicle_shadow) {
    for (const core::ImageRecord& frame : run.dataset.images) {
      const std::optional<std::vector<Vector2>> polygon =
          VehicleShadowPolygon(o, InterpolatePose(run.route.T_map_base, frame.stamp_s));
      if (!polygon) continue;
      nlohmann::ordered_json corners = nlohmann::ordered_json::array();
      for (const Vector2& c : *polygon) corners.push_back({c.x(), c.y()});
      shadows.push_back({{"file", frame.file}, {"polygon_base", std::move(corners)}});
    }
  }
  j["vehicle_shadow_per_frame"] = std::move(shadows);
  // The floor images of the edges of the things standing there, per frame
  // (the camera's position comes from the mount the frame was rendered with).
  nlohmann::ordered_json standing = nlohmann::ordered_json::array();
  if (o.occlusion && o.standing_objects) {
    const std::vector<core::CameraExtrinsicsRecord>& mounts = run.dataset.ground_truth_extrinsics;
    for (const core::ImageRecord& frame : run.dataset.images) {
      const core::SE2 T_map_base = InterpolatePose(run.route.T_map_base, frame.stamp_s);
      const calibration::CameraMount mount =
          mounts.empty() ? run.camera->mount : ToMount(mounts[RecordAt(mounts, frame.stamp_s)]);
      const Eigen::Vector3d camera_base = calibration::BaseFromCamera(mount).translation();
      const Vector2 foot = T_map_base * Vector2(camera_base.x(), camera_base.y());
      const Eigen::Vector3d camera_map(foot.x(), foot.y(), camera_base.z());
      nlohmann::ordered_json segments_base = nlohmann::ordered_json::array();
      for (const NuisanceSegment& s : StandingObjectSegments(
               StandingOccluders(run.world, T_map_base.translation(), kStandingObjectRadiusM),
               camera_map, T_map_base)) {
        segments_base.push_back({s.a_m.x(), s.a_m.y(), s.b_m.x(), s.b_m.y()});
      }
      if (segments_base.empty()) continue;
      standing.push_back({{"file", frame.file}, {"segments_base", std::move(segments_base)}});
    }
  }
  j["standing_objects_per_frame"] = std::move(standing);
  return core::WriteFileAtomically(dir / "nuisance_truth.json", j.dump(1) + "\n");
}

core::Status WriteVehicleTruth(const std::filesystem::path& dir, const SimRun& run) {
  if (!run.dataset.manifest.wheel_encoders) return core::Status::Ok();
  const core::WheelEncoderSensor& nominal = *run.dataset.manifest.wheel_encoders;
  const WheelEncoderLog& log = run.encoder_log;
  nlohmann::ordered_json j;
  j["format"] = "groundline-vehicle-truth";
  j["version"] = "1.0";
  j["note"] = "simulator ground truth: for evaluation only";
  j["nominal"] = {{"wheel_radius_m", nominal.wheel_radius_m}, {"track_m", nominal.track_m}};
  j["left_wheel_radius_m"] = nominal.wheel_radius_m * log.left_radius_scale;
  j["right_wheel_radius_m"] = nominal.wheel_radius_m * log.right_radius_scale;
  j["track_m"] = nominal.track_m * log.track_scale;
  j["wheel_variance_m2_per_m"] = log.wheel_variance_m2_per_m;
  j["slips"] = log.slips.size();
  return core::WriteFileAtomically(dir / "vehicle_truth.json", j.dump(2) + "\n");
}

}  // namespace groundline::sim
