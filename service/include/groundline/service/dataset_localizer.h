// A Localizer (localization/localizer.h) set up from what a dataset
// directory holds, as a site would provide it: the camera's .cameramodel and
// mount file, the wheel geometry and LiDAR block of the manifest, the floor
// map (markings, wall and rack faces) or a given atlas, and the manifest's
// start pose. Shared by `groundline localize --dataset`, `groundline serve`
// and the tests; nothing here reads ground truth or the provenance.
#ifndef GROUNDLINE_SERVICE_DATASET_LOCALIZER_H_
#define GROUNDLINE_SERVICE_DATASET_LOCALIZER_H_

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/core/dataset.h"
#include "groundline/core/status.h"
#include "groundline/localization/floor_front_end.h"
#include "groundline/localization/localizer.h"
#include "groundline/localization/odometry_calibration.h"

namespace groundline::service {

struct DatasetLocalizerOptions {
  localization::LocalizerOptions localizer = localization::LocalizerOptions::ForFusion();
  localization::FloorFrontEndOptions front_end;
  // kLines: the atlas file to localize on; empty: the dataset's floor map.
  std::string atlas_path;
  // kMapping with the LiDAR: the site's surveyed landmarks that tie the
  // built atlas to the site frame, a floor map (.yaml: a handful of surveyed
  // markings, with its survey block) or an atlas file (.json); empty: the
  // start pose alone anchors it. Never the dataset's own floor map.
  std::string surveyed_landmarks_path;
  // The vehicle's odometry calibration (localization/odometry_calibration.h:
  // each wheel's radius, the track, the wheel noise) in place of the
  // manifest's nominal geometry and the options' noise; empty: none.
  std::string odometry_calibration_path;
};

struct DatasetSetup {
  localization::LocalizerSetup setup;
  // Where the atlas came from ("floor_map.yaml", the atlas file, or "empty").
  std::string atlas_source;
  // The camera's mount as commissioned (its extrinsics file), when the mode
  // reads the camera.
  std::optional<calibration::CameraMount> camera_mount;
  // The manifest's start pose, if it has one.
  std::optional<core::StartPose> start_pose;
  double first_reading_s = 0.0;
  // The options to create the localizer with: the given ones, with the
  // odometry calibration's wheel noise when there is one.
  localization::LocalizerOptions options;
  // The odometry calibration in use, if any.
  std::optional<localization::OdometryCalibration> odometry_calibration;
};

// Reads the calibration and the atlas for the localizer's mode. Errors name
// the dataset and the missing or malformed part (no wheel encoders; the
// lines modes without a camera; the LiDAR enabled without a LiDAR; kLines
// without an atlas or a floor map; an unreadable odometry calibration).
core::Result<DatasetSetup> SetupFromDataset(const std::filesystem::path& dir,
                                            const core::Dataset& dataset,
                                            const DatasetLocalizerOptions& options);

// Surveyed landmarks for mapping: a floor map (.yaml, read with its survey
// block) or an atlas (.json). Errors name the file and what was expected.
core::Result<localization::Atlas> ReadSurveyedLandmarks(const std::filesystem::path& path);

// The default start covariance of a start pose (its sigmas, diagonal).
core::Matrix3 StartCovariance(const core::StartPose& start);

}  // namespace groundline::service

#endif  // GROUNDLINE_SERVICE_DATASET_LOCALIZER_H_
