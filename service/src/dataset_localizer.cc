#include "groundline/service/dataset_localizer.h"

#include "groundline/calibration/bev_uncertainty.h"
#include "groundline/calibration/camera_file.h"
#include "groundline/calibration/camera_mount_yaml.h"
#include "groundline/core/floor_map.h"
#include "groundline/localization/atlas.h"

namespace groundline::service {

namespace loc = localization;

core::Matrix3 StartCovariance(const core::StartPose& start) {
  return core::Vector3(start.sigma_xy_m * start.sigma_xy_m, start.sigma_xy_m * start.sigma_xy_m,
                       start.sigma_yaw_rad * start.sigma_yaw_rad)
      .asDiagonal();
}

core::Result<localization::Atlas> ReadSurveyedLandmarks(const std::filesystem::path& path) {
  const std::string extension = path.extension().string();
  if (extension == ".yaml" || extension == ".yml") {
    core::Result<core::FloorMap> map = core::ReadFloorMap(path);
    if (!map.ok()) return map.status();
    return localization::AtlasFromFloorMap(*map, localization::AtlasFromFloorMapOptions());
  }
  if (extension == ".json") return localization::ReadAtlas(path);
  return core::Status::Error(path.string() +
                             ": surveyed landmarks: expected a floor map (.yaml) or an atlas "
                             "(.json), got a '" +
                             extension + "' file");
}

core::Result<DatasetSetup> SetupFromDataset(const std::filesystem::path& dir,
                                            const core::Dataset& dataset,
                                            const DatasetLocalizerOptions& options) {
  const core::DatasetManifest& manifest = dataset.manifest;
  const std::string name = dir.string();
  if (!manifest.wheel_encoders || dataset.wheel_encoders.empty()) {
    return core::Status::Error(name + ": the localizer needs wheel encoder readings");
  }
  const loc::LocalizerOptions& o = options.localizer;
  DatasetSetup out;
  out.first_reading_s = dataset.wheel_encoders.front().stamp_s;
  out.start_pose = manifest.start_pose;
  out.setup.drive.wheel_radius_m = manifest.wheel_encoders->wheel_radius_m;
  out.setup.drive.track_m = manifest.wheel_encoders->track_m;
  out.options = options.localizer;
  if (!options.odometry_calibration_path.empty()) {
    core::Result<loc::OdometryCalibration> calibration =
        loc::ReadOdometryCalibration(options.odometry_calibration_path);
    if (!calibration.ok()) return calibration.status();
    out.setup.drive.left_wheel_radius_m = calibration->drive.LeftRadius();
    out.setup.drive.right_wheel_radius_m = calibration->drive.RightRadius();
    out.setup.drive.track_m = calibration->drive.track_m;
    out.options.wheel_variance_m2_per_m = calibration->wheel_variance_m2_per_m;
    out.options.lateral_variance_m2_per_m = calibration->lateral_variance_m2_per_m;
    out.odometry_calibration = std::move(calibration).value();
  }
  if (manifest.lidar) {
    out.setup.lidar = loc::LidarSetup{manifest.lidar->T_base_lidar, manifest.lidar->rate_hz,
                                      manifest.lidar->stamp};
  }
  const bool floor = o.mode == loc::LocalizerMode::kLines || o.mode == loc::LocalizerMode::kMapping;
  const bool lidar = o.mode == loc::LocalizerMode::kLidar || (floor && o.use_lidar);
  if (lidar && (!manifest.lidar || manifest.files.lidar_scans.empty())) {
    return core::Status::Error(name + ": the LiDAR modes need lidar_scans (no LiDAR)");
  }
  if (floor && !manifest.camera && !lidar) {
    return core::Status::Error(name +
                               ": the lines modes need a camera (or the LiDAR's wall lines)");
  }
  if (floor && manifest.camera) {
    core::Result<calibration::CameraModel> camera =
        calibration::ReadCameraModel(dir / manifest.camera->intrinsics_file);
    if (!camera.ok()) return camera.status();
    core::Result<calibration::CameraMount> mount =
        calibration::ReadCameraMountYaml(dir / manifest.camera->extrinsics_file);
    if (!mount.ok()) return mount.status();
    loc::FloorFrontEndOptions front_end_options = options.front_end;
    if (const std::string& file = manifest.camera->bev_uncertainty_file; !file.empty()) {
      core::Result<calibration::BevUncertaintyMap> map =
          calibration::ReadBevUncertaintyMap(dir / file);
      if (!map.ok()) return map.status();
      if (core::Status s =
              calibration::CheckBevUncertaintyCamera(*map, *camera, (dir / file).string());
          !s.ok()) {
        return s;
      }
      front_end_options.extractor.calibration_floor =
          std::make_shared<const calibration::BevUncertaintyMap>(std::move(map).value());
    }
    core::Result<loc::FloorFrontEnd> front_end =
        loc::FloorFrontEnd::Create(*camera, *mount, front_end_options);
    if (!front_end.ok()) return front_end.status().WithContext(name);
    out.setup.camera = std::make_shared<const loc::FloorFrontEnd>(std::move(front_end).value());
    out.camera_mount = *mount;
  }
  if (!options.surveyed_landmarks_path.empty() &&
      (o.mode != loc::LocalizerMode::kMapping || !o.use_lidar)) {
    return core::Status::Error(options.surveyed_landmarks_path +
                               ": surveyed landmarks anchor a mapping run with the LiDAR; "
                               "expected the mapping mode with the LiDAR on");
  }
  if (o.mode == loc::LocalizerMode::kLines) {
    if (!options.atlas_path.empty()) {
      core::Result<loc::Atlas> atlas = loc::ReadAtlas(options.atlas_path);
      if (!atlas.ok()) return atlas.status();
      out.setup.atlas = std::move(atlas).value();
      out.atlas_source = options.atlas_path;
    } else if (dataset.floor_map) {
      out.setup.atlas = loc::AtlasFromFloorMap(*dataset.floor_map, loc::AtlasFromFloorMapOptions());
      out.atlas_source = manifest.files.floor_map;
    } else {
      return core::Status::Error(name +
                                 ": the lines mode needs an atlas file or a dataset with "
                                 "floor_map.yaml");
    }
  } else if (!options.surveyed_landmarks_path.empty()) {
    core::Result<loc::Atlas> survey = ReadSurveyedLandmarks(options.surveyed_landmarks_path);
    if (!survey.ok()) return survey.status();
    out.setup.atlas = std::move(survey).value();
    out.atlas_source = options.surveyed_landmarks_path;
  } else {
    out.atlas_source = "empty";
  }
  return out;
}

}  // namespace groundline::service
