// The sensor records of a groundline dataset and the text files that hold
// them (format: docs/dataset.md).
//
// All stamps are seconds (float64) in the one clock of the dataset, and
// strictly increase within each file. Files are written with fixed precision
// (stamps and wheel deltas 9 decimals, ranges and range limits 4 decimals,
// intensities 6 significant digits; scan angles exactly, as the shortest text
// that reads back to the same double) through std::to_chars, so output does
// not depend on the C locale.
//
// Readers validate everything they parse and return an error that names the
// file, the line, the field and what was expected, e.g.
//   "d/wheel_encoders.csv:7: field 'left_delta_rad': expected a finite number, got 'nan'".
// A file whose last line lacks its '\n' is reported as truncated. Writers run
// the same checks first (with the line the record would occupy) and write
// atomically, so they never produce a file their reader rejects.
#ifndef GROUNDLINE_CORE_DATASET_RECORDS_H_
#define GROUNDLINE_CORE_DATASET_RECORDS_H_

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "groundline/core/status.h"

namespace groundline::core {

// One camera image: images/index.csv, header "stamp_s,file".
struct ImageRecord {
  double stamp_s = 0.0;  // mid-exposure
  // PNG file name relative to the directory of the index file; '/'-separated,
  // relative, no "..", ending in ".png".
  std::string file;
};

// Wheel encoder increments: wheel_encoders.csv, header
// "stamp_s,left_delta_rad,right_delta_rad". Each delta is the wheel's rotation
// over (previous stamp, this stamp], positive when the wheel drives the
// vehicle forward; distance rolled = delta_rad * wheel_radius_m. The first
// reading's deltas cover an interval before the file starts: integrators start
// at the first reading and apply deltas from the second on (writers put 0).
struct WheelEncoderReading {
  double stamp_s = 0.0;
  double left_delta_rad = 0.0;
  double right_delta_rad = 0.0;
};

// The range of a beam without a valid return (no echo, out of range, dropped).
// Exactly zero, never NaN or inf; unambiguous because range_min_m >= 1 mm.
inline constexpr double kNoReturnRange_m = 0.0;
// The smallest range_min_m a scan may declare (keeps kNoReturnRange_m distinct
// from any return at the written precision of 0.1 mm).
inline constexpr double kMinRangeLimit_m = 1e-3;

// One planar LiDAR scan in the LiDAR frame (x forward, y left, z up;
// T_base_lidar in the manifest). Beam i points at
// angle_min_rad + i * angle_increment_rad (counter-clockwise from x). The
// stamp holds for the whole scan (beams treated as simultaneous).
struct LaserScan {
  double stamp_s = 0.0;
  double angle_min_rad = 0.0;
  double angle_increment_rad = 0.0;  // != 0; negative for clockwise scanners
  double range_min_m = 0.0;          // >= kMinRangeLimit_m
  double range_max_m = 0.0;          // > range_min_m
  // Each either kNoReturnRange_m or within [range_min_m, range_max_m].
  std::vector<double> ranges_m;
  // Empty, or one finite value >= 0 per beam, in the device's units.
  std::vector<double> intensities;

  double BeamAngle_rad(std::size_t i) const {
    return angle_min_rad + static_cast<double>(i) * angle_increment_rad;
  }
  bool IsReturn(std::size_t i) const { return ranges_m[i] != kNoReturnRange_m; }
};

// The camera's true mount over time, for simulated datasets (format >= 1.1):
// ground_truth_extrinsics.csv, header
// "stamp_s,height_m,pitch_rad,roll_rad,yaw_rad,forward_m,lateral_m".
// The fields are those of the calibration module's CameraMount (the groundline
// extrinsics of docs/conventions.md: optical centre height_m above the floor,
// forward_m ahead and lateral_m left of base_link, pitch down, roll about the
// optical axis, yaw left). The mount is piecewise constant: a record holds from
// its stamp until the next record's stamp (the first record from the start of
// the dataset). Checks: finite fields, height_m > 0, |pitch_rad| < pi/2, roll
// and yaw in [-pi, pi]. Written with 9 decimals.
struct CameraExtrinsicsRecord {
  double stamp_s = 0.0;
  double height_m = 0.0;
  double pitch_rad = 0.0;
  double roll_rad = 0.0;
  double yaw_rad = 0.0;
  double forward_m = 0.0;
  double lateral_m = 0.0;
};

// Whole-file readers and writers. ReadImageIndex also checks that every
// listed image file exists when `check_files` is set (it never decodes them).
Result<std::vector<ImageRecord>> ReadImageIndex(const std::filesystem::path& path,
                                                bool check_files = true);
Status WriteImageIndex(const std::filesystem::path& path, const std::vector<ImageRecord>& images);

Result<std::vector<WheelEncoderReading>> ReadWheelEncoders(const std::filesystem::path& path);
Status WriteWheelEncoders(const std::filesystem::path& path,
                          const std::vector<WheelEncoderReading>& readings);

Result<std::vector<CameraExtrinsicsRecord>> ReadGroundTruthExtrinsics(
    const std::filesystem::path& path);
Status WriteGroundTruthExtrinsics(const std::filesystem::path& path,
                                  const std::vector<CameraExtrinsicsRecord>& records);

// lidar_scans.txt: a header comment line (kLaserScanFileHeader), then one scan
// per line, whitespace separated:
//   stamp_s angle_min_rad angle_increment_rad range_min_m range_max_m
//   n range_1 ... range_n m intensity_1 ... intensity_m      (m is 0 or n)
inline constexpr char kLaserScanFileHeader[] =
    "# groundline lidar_scans v1: stamp_s angle_min_rad angle_increment_rad range_min_m "
    "range_max_m n ranges_m[n] m intensities[m]";
Result<std::vector<LaserScan>> ReadLaserScans(const std::filesystem::path& path);
Status WriteLaserScans(const std::filesystem::path& path, const std::vector<LaserScan>& scans);

// Reads lidar_scans.txt one scan at a time (constant memory for long runs),
// with the same validation as ReadLaserScans. Not thread-safe; movable.
class LaserScanReader {
 public:
  // Opens the file and checks its header line.
  static Result<LaserScanReader> Open(const std::filesystem::path& path);

  LaserScanReader(LaserScanReader&&) noexcept;
  LaserScanReader& operator=(LaserScanReader&&) noexcept;
  ~LaserScanReader();

  // Reads the next scan into *scan: true if one was read, false at the end of
  // the file, an error for a malformed line (the reader is then exhausted).
  Result<bool> Next(LaserScan* scan);
  // The file's name and the line of the scan last read (for messages).
  const std::string& file() const;
  std::size_t line() const;

 private:
  struct Impl;
  explicit LaserScanReader(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_DATASET_RECORDS_H_
