// A small synthetic dataset for the dataset tests, and helpers to edit its
// files line by line.
#ifndef GROUNDLINE_TESTS_CORE_DATASET_FIXTURE_H_
#define GROUNDLINE_TESTS_CORE_DATASET_FIXTURE_H_

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "groundline/core/dataset.h"
#include "test_data.h"
#include "test_units.h"

namespace groundline::testing {

inline void WriteText(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// Lines of a file without their '\n'; WriteLines adds one after each.
inline std::vector<std::string> ReadLines(const std::filesystem::path& path) {
  std::vector<std::string> lines;
  std::istringstream in(ReadText(path));
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

inline void WriteLines(const std::filesystem::path& path, const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  WriteText(path, text);
}

// Replaces the first occurrence of `from` in the file; fails the test if absent.
inline void ReplaceInFile(const std::filesystem::path& path, const std::string& from,
                          const std::string& to) {
  std::string text = ReadText(path);
  const std::size_t at = text.find(from);
  ASSERT_NE(at, std::string::npos) << "'" << from << "' not in " << path;
  text.replace(at, from.size(), to);
  WriteText(path, text);
}

// The 1-based number of the first line of `path` containing `needle`, 0 if none.
inline std::size_t LineContaining(const std::filesystem::path& path, const std::string& needle) {
  const std::vector<std::string> lines = ReadLines(path);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].find(needle) != std::string::npos) return i + 1;
  }
  return 0;
}

// A 2 s run at 1 m/s along a gentle left arc: 5 images (10 Hz), 101 encoder
// readings (50 Hz), 4 scans of 181 beams (12.5 Hz) (one without intensities, some beams
// without return), 101 ground-truth poses, and four floor markings. Writes the
// calibration files and placeholder images into `dir`: the core reader only
// checks that they exist (they are file-existence fixtures, not real PNGs).
inline core::Dataset MakeSyntheticDataset(const std::filesystem::path& dir) {
  using core::Vector2;
  using ::groundline::testing::kPi;
  core::Dataset d;
  core::DatasetManifest& m = d.manifest;
  m.name = "unit_synthetic";
  m.description = "Aisle 3: \"loop\" test, # not a comment\nsecond line";
  m.camera =
      core::CameraSensor{640, 400, 10.0, "calibration/camera.yaml", "calibration/extrinsics.yaml"};
  m.wheel_encoders = core::WheelEncoderSensor{50.0, 0.1, 0.5, 4096};
  m.lidar = core::LidarSensor{12.5, core::SE2(0.3, -0.02, kPi - 1e-7), 0.25, 0.05, 30.0};
  m.provenance = {
      {"generator", "groundline-sim (test)"}, {"seed", "42"}, {"zone", "A"}, {"note", "null"}};
  WriteText(dir / "calibration/camera.yaml", "placeholder intrinsics\n");
  WriteText(dir / "calibration/extrinsics.yaml", "placeholder extrinsics\n");

  const double t0_s = 1700000000.0;  // an epoch-like clock
  const double speed_mps = 1.0, yaw_rate_radps = 0.2, radius_m = 0.1, track_m = 0.5;
  for (int i = 0; i <= 100; ++i) {
    const double t = 0.02 * i;
    const double yaw = yaw_rate_radps * t;
    core::StampedPose p;
    p.stamp_s = t0_s + t;
    p.pose = core::SE2(speed_mps / yaw_rate_radps * std::sin(yaw),
                       speed_mps / yaw_rate_radps * (1.0 - std::cos(yaw)), yaw);
    d.ground_truth.push_back(p);
    const double dt = i == 0 ? 0.0 : 0.02;
    d.wheel_encoders.push_back({t0_s + t,
                                (speed_mps - 0.5 * track_m * yaw_rate_radps) * dt / radius_m,
                                (speed_mps + 0.5 * track_m * yaw_rate_radps) * dt / radius_m});
  }
  for (int i = 0; i < 5; ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "%06d.png", i);
    d.images.push_back({t0_s + 0.005 + 0.1 * i, name});
    WriteText(dir / "images" / name, "not a PNG: file-existence fixture\n");
  }
  std::mt19937 rng(1234);
  std::uniform_real_distribution<double> range_m(0.05, 30.0), intensity(0.0, 5000.0);
  for (int s = 0; s < 4; ++s) {
    core::LaserScan scan;
    scan.stamp_s = t0_s + 0.033 + 0.08 * s;
    scan.angle_min_rad = -kPi / 2;
    scan.angle_increment_rad = kPi / 180;
    scan.range_min_m = 0.05;
    scan.range_max_m = 30.0;
    for (int b = 0; b < 181; ++b) {
      const bool no_return = b % 17 == 3;
      scan.ranges_m.push_back(no_return ? core::kNoReturnRange_m : range_m(rng));
      if (s != 2) scan.intensities.push_back(no_return ? 0.0 : intensity(rng));
    }
    scan.ranges_m[10] = 0.05;  // exactly the limits
    scan.ranges_m[11] = 30.0;
    d.scans.push_back(scan);
  }
  core::FloorMap map;
  const auto marking = [](std::int64_t id, core::MarkingKind kind, double width_m,
                          std::array<int, 3> rgb, core::MarkingPolarity polarity,
                          std::vector<Vector2> polyline_m) {
    core::FloorMarking m;
    m.id = id;
    m.kind = kind;
    m.width_m = width_m;
    m.colour_rgb = rgb;
    m.polarity = polarity;
    m.polyline_m = std::move(polyline_m);
    return m;
  };
  using core::MarkingKind;
  constexpr core::MarkingPolarity kBright = core::MarkingPolarity::kBright;
  core::FloorMarking dashed = marking(7, MarkingKind::kTapeDashed, 0.05, {255, 210, 0}, kBright,
                                      {Vector2(0.0, 1.2), Vector2(20.0, 1.2), Vector2(25.1, 3.3)});
  dashed.dash_m = 0.5;
  dashed.gap_m = 0.25;
  const core::FloorMarking stop = marking(8, MarkingKind::kStopBar, 0.1, {255, 255, 255}, kBright,
                                          {Vector2(5.0, -1.0), Vector2(5.0, 1.0)});
  const core::FloorMarking joint =
      marking(9, MarkingKind::kJoint, 0.006, {60, 60, 60}, core::MarkingPolarity::kDark,
              {Vector2(-10.0, 0.1), Vector2(30.0, 0.1)});
  const core::FloorMarking box =
      marking(10, MarkingKind::kStagingBoxEdge, 0.075, {0, 90, 200}, kBright,
              {Vector2(1, 2), Vector2(3, 2), Vector2(3, 4), Vector2(1, 4), Vector2(1, 2)});
  map.markings = {dashed, stop, joint, box};
  map.survey = core::FloorMapSurvey{0.003, 0.02, 0.0035};
  d.floor_map = map;
  d.UseDefaultFileNames();
  return d;
}

}  // namespace groundline::testing

#endif  // GROUNDLINE_TESTS_CORE_DATASET_FIXTURE_H_
