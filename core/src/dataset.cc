// Reading and writing a whole dataset directory.
#include "groundline/core/dataset.h"

#include <cmath>
#include <functional>
#include <string>
#include <system_error>
#include <vector>

#include "dataset_internal.h"
#include "groundline/core/text_parse.h"
#include "groundline/core/trajectory_io.h"
#include "text_lines.h"

namespace groundline::core {
namespace {

// Scans repeat the manifest's range limits at the written precision (0.1 mm).
constexpr double kRangeLimitTolerance_m = 5e-5 + 1e-9;
constexpr char kStagingSuffix[] = ".new";

Status ReadScans(const std::filesystem::path& path, const LidarSensor& lidar,
                 std::vector<LaserScan>* scans) {
  Result<LaserScanReader> reader = LaserScanReader::Open(path);
  if (!reader.ok()) return reader.status();
  LaserScan scan;
  while (true) {
    const Result<bool> more = reader->Next(&scan);
    if (!more.ok()) return more.status();
    if (!*more) return Status::Ok();
    const std::pair<const char*, double> limits[] = {{"range_min_m", lidar.range_min_m},
                                                     {"range_max_m", lidar.range_max_m}};
    const double values[] = {scan.range_min_m, scan.range_max_m};
    for (int k = 0; k < 2; ++k) {
      if (std::abs(values[k] - limits[k].second) > kRangeLimitTolerance_m) {
        return Status::Error(FieldError(reader->file(), reader->line(), limits[k].first,
                                        "the manifest's sensors.lidar." +
                                            std::string(limits[k].first) + " = " +
                                            internal::FormatShortest(limits[k].second),
                                        internal::FormatShortest(values[k])));
      }
    }
    scans->push_back(scan);
  }
}

Status ReadGroundTruth(const std::filesystem::path& path, Trajectory* ground_truth) {
  if (Status s = internal::CheckEndsWithNewline(path); !s.ok()) return s;
  Result<Trajectory> read = ReadTumTrajectory(path);
  if (!read.ok()) return read.status();
  *ground_truth = std::move(read).value();
  return Status::Ok();
}

// The parts of a dataset as (relative file, writer) pairs, in writing order.
struct Part {
  std::string file;
  std::function<Status(const std::filesystem::path&)> write;
};

Status CheckPartsMatchFiles(const Dataset& d) {
  const DatasetFiles& f = d.manifest.files;
  const struct {
    std::size_t count;
    const std::string& file;
    const char* what;
    const char* key;
  } parts[] = {
      {d.images.size(), f.image_index, "images", "image_index"},
      {d.wheel_encoders.size(), f.wheel_encoders, "wheel encoder readings", "wheel_encoders"},
      {d.scans.size(), f.lidar_scans, "scans", "lidar_scans"},
      {d.ground_truth.size(), f.ground_truth, "ground-truth poses", "ground_truth"},
      {d.floor_map ? 1u : 0u, f.floor_map, "floor map(s)", "floor_map"},
      {d.ground_truth_extrinsics.size(), f.ground_truth_extrinsics, "ground-truth extrinsics",
       "ground_truth_extrinsics"}};
  for (const auto& part : parts) {
    if (part.count > 0 && part.file.empty()) {
      return Status::Error("dataset has " + std::to_string(part.count) + " " + part.what +
                           " but manifest.files." + part.key +
                           " is empty (see Dataset::UseDefaultFileNames)");
    }
  }
  if (!f.floor_map.empty() && !d.floor_map) {
    return Status::Error("manifest.files.floor_map is '" + f.floor_map +
                         "' but the dataset has no floor map");
  }
  return Status::Ok();
}

void RemoveStaged(const std::filesystem::path& dir, const std::vector<Part>& parts) {
  std::error_code ec;
  for (const Part& part : parts) {
    std::filesystem::remove(dir / (part.file + kStagingSuffix), ec);
  }
}

}  // namespace

void Dataset::UseDefaultFileNames() {
  DatasetFiles& f = manifest.files;
  f.image_index = manifest.camera ? kDefaultImageIndexFile : "";
  f.wheel_encoders = manifest.wheel_encoders ? kDefaultWheelEncodersFile : "";
  f.lidar_scans = manifest.lidar ? kDefaultLidarScansFile : "";
  f.ground_truth = ground_truth.empty() ? "" : kDefaultGroundTruthFile;
  f.floor_map = floor_map ? kDefaultFloorMapFile : "";
  f.ground_truth_extrinsics =
      ground_truth_extrinsics.empty() ? "" : kDefaultGroundTruthExtrinsicsFile;
}

Result<Dataset> ReadDataset(const std::filesystem::path& dir, const DatasetReadOptions& options) {
  const std::filesystem::path manifest_path = dir / kManifestFileName;
  if (!std::filesystem::is_regular_file(manifest_path)) {
    return Status::Error(dir.string() + ": no " + kManifestFileName +
                         ": not a groundline dataset, or one whose writing did not complete");
  }
  Result<DatasetManifest> manifest = ReadDatasetManifest(manifest_path);
  if (!manifest.ok()) return manifest.status();
  Dataset d;
  d.manifest = std::move(manifest).value();
  const DatasetFiles& f = d.manifest.files;
  if (!f.image_index.empty() && options.load_images) {
    auto images = ReadImageIndex(dir / f.image_index, options.check_image_files);
    if (!images.ok()) return images.status();
    d.images = std::move(images).value();
  }
  if (!f.wheel_encoders.empty() && options.load_wheel_encoders) {
    auto readings = ReadWheelEncoders(dir / f.wheel_encoders);
    if (!readings.ok()) return readings.status();
    d.wheel_encoders = std::move(readings).value();
  }
  if (!f.lidar_scans.empty() && options.load_scans) {
    if (Status s = ReadScans(dir / f.lidar_scans, *d.manifest.lidar, &d.scans); !s.ok()) return s;
  }
  if (!f.ground_truth.empty() && options.load_ground_truth) {
    if (Status s = ReadGroundTruth(dir / f.ground_truth, &d.ground_truth); !s.ok()) return s;
  }
  if (!f.ground_truth_extrinsics.empty() && options.load_ground_truth) {
    auto records = ReadGroundTruthExtrinsics(dir / f.ground_truth_extrinsics);
    if (!records.ok()) return records.status();
    d.ground_truth_extrinsics = std::move(records).value();
  }
  if (!f.floor_map.empty() && options.load_floor_map) {
    auto map = internal::ReadFloorMapInFrame(dir / f.floor_map, d.manifest.frames.map);
    if (!map.ok()) return map.status();
    d.floor_map = std::move(map).value();
  }
  return d;
}

Status WriteDataset(const std::filesystem::path& dir, const Dataset& d) {
  const DatasetManifest& m = d.manifest;
  if (Status s = m.Validate(); !s.ok()) return s.WithContext(dir.string());
  if (Status s = CheckPartsMatchFiles(d); !s.ok()) return s.WithContext(dir.string());
  if (m.camera) {
    for (const std::string& file : {m.camera->intrinsics_file, m.camera->extrinsics_file,
                                    m.camera->bev_uncertainty_file}) {
      if (file.empty()) continue;  // an optional file not given
      if (!std::filesystem::is_regular_file(dir / file)) {
        return Status::Error(dir.string() + ": calibration file '" + file +
                             "' referenced by sensors.camera is missing; write it first");
      }
    }
  }
  const DatasetFiles& f = m.files;
  std::vector<Part> parts;
  if (!f.image_index.empty()) {
    parts.push_back({f.image_index, [&d](const auto& p) { return WriteImageIndex(p, d.images); }});
  }
  if (!f.wheel_encoders.empty()) {
    parts.push_back({f.wheel_encoders,
                     [&d](const auto& p) { return WriteWheelEncoders(p, d.wheel_encoders); }});
  }
  if (!f.lidar_scans.empty()) {
    parts.push_back({f.lidar_scans, [&d](const auto& p) { return WriteLaserScans(p, d.scans); }});
  }
  if (!f.ground_truth.empty()) {
    parts.push_back(
        {f.ground_truth, [&d](const auto& p) { return WriteTumTrajectory(p, d.ground_truth); }});
  }
  if (!f.ground_truth_extrinsics.empty()) {
    parts.push_back({f.ground_truth_extrinsics, [&d](const auto& p) {
                       return WriteGroundTruthExtrinsics(p, d.ground_truth_extrinsics);
                     }});
  }
  if (!f.floor_map.empty()) {
    parts.push_back({f.floor_map, [&d](const auto& p) { return WriteFloorMap(p, *d.floor_map); }});
  }
  // Phase 1: every file is written (and validated) beside its destination.
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const std::filesystem::path staged = dir / (parts[i].file + kStagingSuffix);
    if (Status s = parts[i].write(staged); !s.ok()) {
      RemoveStaged(dir, parts);
      // Name the file as the dataset will, not its staging name.
      std::string message = s.message();
      const std::string from = staged.string(), to = (dir / parts[i].file).string();
      for (std::size_t at = message.find(from); at != std::string::npos;
           at = message.find(from, at + to.size())) {
        message.replace(at, from.size(), to);
      }
      return Status::Error(message);
    }
  }
  // Phase 2: retire the old manifest, move the files into place, and write
  // the manifest last.
  std::error_code ec;
  std::filesystem::remove(dir / kManifestFileName, ec);
  if (ec) {
    RemoveStaged(dir, parts);
    return Status::Error("cannot remove the old manifest in " + dir.string() + ": " + ec.message());
  }
  for (const Part& part : parts) {
    std::filesystem::rename(dir / (part.file + kStagingSuffix), dir / part.file, ec);
    if (ec) {
      RemoveStaged(dir, parts);
      return Status::Error("cannot move " + part.file + " into place in " + dir.string() + ": " +
                           ec.message());
    }
  }
  return WriteDatasetManifest(dir / kManifestFileName, m);
}

}  // namespace groundline::core
