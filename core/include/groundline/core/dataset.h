// The groundline dataset: what the simulator writes, what converters of real
// logs produce, and what the localization service replays (a warehouse AGV
// with a downward-tilted floor camera, two wheel encoders and a planar LiDAR).
// The on-disk format is specified in docs/dataset.md; in short, a directory:
//
//   manifest.yaml        format, version, sensors, frames, files, provenance
//   images/index.csv     stamp_s,file  (+ the PNG files, never decoded here)
//   wheel_encoders.csv   stamp_s,left_delta_rad,right_delta_rad
//   lidar_scans.txt      one scan per line
//   ground_truth.tum     T_map_base (TUM, see trajectory_io.h)
//   floor_map.yaml       optional ground-truth floor markings (floor_map.h)
//   ground_truth_extrinsics.csv  optional (1.1): the camera's true mount over time
//   calibration/...      camera intrinsics and extrinsics, referenced only
//
// Units are SI (m, rad, s, Hz), frames follow REP-105 (map, odom, base_link),
// stamps are float64 seconds in one clock shared by every file.
//
// Versioning: `version: MAJOR.MINOR`. A reader accepts its own major version
// and rejects any other with a message saying which it supports. Within a
// major version, a minor bump only adds optional keys or files: a reader
// rejects unknown keys in a file of a minor version it knows (typos are
// caught), and ignores them in a newer minor version.
#ifndef GROUNDLINE_CORE_DATASET_H_
#define GROUNDLINE_CORE_DATASET_H_

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "groundline/core/dataset_records.h"
#include "groundline/core/floor_map.h"
#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/core/trajectory.h"

namespace groundline::core {

inline constexpr char kDatasetFormatName[] = "groundline-dataset";
inline constexpr int kDatasetFormatMajor = 1;
// 1.1 added files.ground_truth_extrinsics (ground_truth_extrinsics.csv);
// 1.2 added sensors.lidar.stamp and start_pose.
inline constexpr int kDatasetFormatMinor = 2;
inline constexpr char kManifestFileName[] = "manifest.yaml";

// Default file names, relative to the dataset directory.
inline constexpr char kDefaultImageIndexFile[] = "images/index.csv";
inline constexpr char kDefaultWheelEncodersFile[] = "wheel_encoders.csv";
inline constexpr char kDefaultLidarScansFile[] = "lidar_scans.txt";
inline constexpr char kDefaultGroundTruthFile[] = "ground_truth.tum";
inline constexpr char kDefaultFloorMapFile[] = "floor_map.yaml";
inline constexpr char kDefaultGroundTruthExtrinsicsFile[] = "ground_truth_extrinsics.csv";

struct CameraSensor {
  int image_width_px = 0;   // > 0
  int image_height_px = 0;  // > 0
  double rate_hz = 0.0;     // nominal frame rate, > 0
  // Relative to the dataset directory; must exist. Parsed by the calibration
  // module (mrcal/OpenCV intrinsics, groundline extrinsics T_base_cam).
  std::string intrinsics_file = "calibration/camera.yaml";
  std::string extrinsics_file = "calibration/extrinsics.yaml";
  // Optional (empty: none): the calibration's floor uncertainty that
  // `calibrate floor` wrote (bev_uncertainty.json), the floor of the line
  // covariances (calibration/bev_uncertainty.h).
  std::string bev_uncertainty_file{};
};

struct WheelEncoderSensor {
  double rate_hz = 0.0;            // nominal, > 0
  double wheel_radius_m = 0.0;     // > 0, both drive wheels
  double track_m = 0.0;            // > 0, distance between the wheels' contact points
  std::int64_t ticks_per_rev = 0;  // > 0, encoder resolution (deltas need not be multiples)
};

// Which instant a scan's stamp_s names (file spelling "mid_sweep" /
// "first_ray"). A sweeping scanner's rays are spread over one revolution;
// a match of the whole scan estimates the pose at the middle of the sweep.
// The ROS LaserScan stamp is the first ray's time.
enum class LidarStamp { kMidSweep, kFirstRay };

struct LidarSensor {
  double rate_hz = 0.0;         // nominal, > 0
  SE2 T_base_lidar;             // mounting pose of the LiDAR frame in base_link
  double mount_height_m = 0.0;  // scan plane above the floor, >= 0
  double range_min_m = 0.0;     // >= kMinRangeLimit_m; every scan repeats it
  double range_max_m = 0.0;     // > range_min_m; every scan repeats it
  // Since 1.2. Older files: mid_sweep, except those whose provenance says
  // they come from `groundline sim` without `lidar_stamp: mid_sweep` (first
  // ray), which the reader maps here.
  LidarStamp stamp = LidarStamp::kMidSweep;
};

// Since 1.2, optional: where the vehicle starts, as the site knows it (its
// dock or charging station, from the fleet manager), with its uncertainty
// (1 sigma; > 0). A localizer starts from it when no other start is given.
struct StartPose {
  double stamp_s = 0.0;  // when it stood there: at or before the first wheel reading
  SE2 T_map_base;
  double sigma_xy_m = 0.005;
  double sigma_yaw_rad = 0.0017453292519943296;  // 0.1 deg
};

// Frame names (REP-105); configurable for namespaced fleets ("agv7/base_link").
struct DatasetFrames {
  std::string map = "map";
  std::string odom = "odom";
  std::string base_link = "base_link";
};

// Relative paths ('/'-separated, no "..") of the files present; empty means
// absent. A sensor is present iff its stream file is: camera <-> image_index,
// wheel_encoders <-> wheel_encoders, lidar <-> lidar_scans.
struct DatasetFiles {
  std::string image_index;
  std::string wheel_encoders;
  std::string lidar_scans;
  std::string ground_truth;
  std::string floor_map;
  // Since 1.1, optional: the camera's true mount over time (simulated data;
  // requires sensors.camera).
  std::string ground_truth_extrinsics;
};

struct DatasetManifest {
  // On reading: the version found in the file. Writers always write the
  // current kDatasetFormatMajor.kDatasetFormatMinor.
  int version_major = kDatasetFormatMajor;
  int version_minor = kDatasetFormatMinor;
  std::string name;  // non-empty
  std::string description;
  DatasetFrames frames;
  std::optional<CameraSensor> camera;
  std::optional<WheelEncoderSensor> wheel_encoders;
  std::optional<LidarSensor> lidar;
  std::optional<StartPose> start_pose;
  DatasetFiles files;
  // Free-form scalars: generator, seed, zone, source log, ...
  std::map<std::string, std::string> provenance;

  // The checks ReadDatasetManifest makes, except file existence.
  Status Validate() const;
};

struct Dataset {
  DatasetManifest manifest;
  std::vector<ImageRecord> images;
  std::vector<WheelEncoderReading> wheel_encoders;
  std::vector<LaserScan> scans;
  Trajectory ground_truth;  // T_map_base
  std::optional<FloorMap> floor_map;
  // The camera's true mount over time (dataset_records.h); empty when absent.
  std::vector<CameraExtrinsicsRecord> ground_truth_extrinsics;

  // Sets manifest.files to the default name of every part present (a sensor
  // in the manifest, non-empty ground truth, a floor map) and empties the rest.
  void UseDefaultFileNames();
};

// Which parts ReadDataset parses. Skipped parts are still checked for
// existence (the manifest references them) but left empty.
struct DatasetReadOptions {
  bool load_images = true;
  bool check_image_files = true;  // stat every image listed in the index
  bool load_wheel_encoders = true;
  bool load_scans = true;
  bool load_ground_truth = true;  // also the ground-truth extrinsics
  bool load_floor_map = true;
};

// Reads and validates `dir`. Beyond each file's own checks: every referenced
// file exists, every scan repeats the manifest's range limits (within 5e-5 m,
// half the written precision), the floor map's frame is the manifest's map frame,
// and the ground truth file ends with a newline (not cut mid-way).
Result<Dataset> ReadDataset(const std::filesystem::path& dir,
                            const DatasetReadOptions& options = {});

// Writes `dataset` into `dir` (created if missing). The images and the
// calibration files must already be in place (they are checked, not written).
// An existing manifest is removed first and the new one written last, each
// file atomically, so a reader that finds a manifest finds complete files.
// Everything is validated before the first write: on a validation error the
// directory is left untouched.
Status WriteDataset(const std::filesystem::path& dir, const Dataset& dataset);

// The manifest alone. ReadDatasetManifest checks that every file it
// references exists relative to the manifest's directory.
Result<DatasetManifest> ReadDatasetManifest(const std::filesystem::path& path);
Status WriteDatasetManifest(const std::filesystem::path& path, const DatasetManifest& manifest);

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_DATASET_H_
