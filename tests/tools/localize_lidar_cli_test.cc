// `groundline localize --mode lidar` end to end on a short simulated zone B
// run (no camera): the LiDAR + odometry trajectory beats dead reckoning, and
// the health carries the degeneracy fields and the ground-truth region, and
// `eval --zone` prints the degeneracy detector's shares from its summary.
// `groundline localize --carmen` on a real log written out of order, and with
// its laser lines written without a pose.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cli_runner.h"
#include "groundline/io/compressed_file.h"
#include "test_data.h"
#include "tools_under_test.h"

namespace groundline {
namespace {

using testing::Quoted;
using testing::ReadJson;
using testing::RunGroundline;

// The lines of a test log, one per line.
void WriteLines(const std::filesystem::path& path, const std::vector<std::string>& text) {
  std::ofstream out(path);
  for (const std::string& l : text) out << l << "\n";
}

// The relations of ACES whose two stamps are both at most end_s, into
// dir/minute.relations.
void WriteAcesRelationsUpTo(const std::filesystem::path& data, double end_s,
                            const std::filesystem::path& dir) {
  std::ifstream in(data / "aces.relations");
  std::ofstream out(dir / "minute.relations");
  for (std::string line; std::getline(in, line);) {
    double t1 = 0.0, t2 = 0.0;
    std::istringstream fields(line);
    if (fields >> t1 >> t2 && t1 <= end_s && t2 <= end_s) out << line << "\n";
  }
}

// `localize --carmen dir/log --relations dir/minute.relations --out
// dir/out_name`: its summary.json and what it printed.
std::pair<nlohmann::json, std::string> RunCarmen(const std::filesystem::path& dir,
                                                 const std::string& log,
                                                 const std::string& out_name) {
  std::string out;
  EXPECT_EQ(RunGroundline("localize --carmen " + Quoted(dir / log) + " --relations " +
                              Quoted(dir / "minute.relations") + " --out " +
                              Quoted(dir / out_name),
                          dir, &out),
            0)
      << out;
  return {ReadJson(dir / out_name / "summary.json"), out};
}

TEST(LocalizeLidarCli, LidarBeatsOdometryOnAShortZoneBRun) {
  if (::groundline::testing::Sanitized()) {
    // ~4 min of a Debug executable's scan matching under ASan; 1.5 s in release.
    GTEST_SKIP() << "too slow under AddressSanitizer (Debug); runs in the release build";
  }
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("localize_lidar");
  const std::filesystem::path dataset = dir / "zone_b";
  std::string out;
  ASSERT_EQ(RunGroundline("sim --zone B --length 15m --seed 3 --no-camera --out " + Quoted(dataset),
                          dir, &out),
            0)
      << out;
  const std::filesystem::path lidar = dir / "lidar", odometry = dir / "odometry";
  ASSERT_EQ(RunGroundline(
                "localize --dataset " + Quoted(dataset) + " --mode lidar --out " + Quoted(lidar),
                dir, &out),
            0)
      << out;
  ASSERT_EQ(RunGroundline("localize --dataset " + Quoted(dataset) + " --out " + Quoted(odometry),
                          dir, &out),
            0)
      << out;
  const nlohmann::json with_lidar = ReadJson(lidar / "summary.json");
  const double ate_lidar = with_lidar["accuracy"]["ate_rmse_m"].get<double>();
  const double ate_odometry =
      ReadJson(odometry / "summary.json")["accuracy"]["ate_rmse_m"].get<double>();
  // Measured: 0.06 m against 0.13 m.
  EXPECT_LT(ate_lidar, 0.7 * ate_odometry);
  EXPECT_GT(with_lidar["counters"]["scans_matched"].get<int>(), 100);

  std::ifstream health(lidar / "health.jsonl");
  std::string line;
  int lines = 0, flagged = 0;
  while (std::getline(health, line)) {
    const nlohmann::json h = nlohmann::json::parse(line);
    ASSERT_TRUE(h.contains("lidar_degenerate")) << line;
    ASSERT_EQ(h["lidar_scaled_eigenvalues"].size(), 3u) << line;
    ASSERT_EQ(h["lidar_weakest_direction"].size(), 3u) << line;
    ASSERT_FALSE(h.contains("region")) << "ground truth in a product output: " << line;
    ++lines;
    flagged += h["lidar_degenerate"].get<bool>() ? 1 : 0;
  }
  EXPECT_GT(lines, 50);
  EXPECT_EQ(with_lidar["counters"]["lidar_degenerate"].get<int>(), flagged);

  // The zone table adds the detector's shares per region of the zone, from
  // health.jsonl and the ground truth (evaluation only).
  ASSERT_EQ(RunGroundline("eval --dataset " + Quoted(dataset) + " --zone B --run lidar=" +
                              Quoted(lidar) + " --assoc interp --max-dt-s 0.05",
                          dir, &out),
            0)
      << out;
  ASSERT_NE(out.find("LiDAR degeneracy detector"), std::string::npos) << out;
  // Every keyframe falls in some region, and the shares add up to it.
  int counted = 0;
  for (std::size_t at = out.find('/'); at != std::string::npos; at = out.find('/', at + 1)) {
    const std::size_t end = out.find(' ', at);
    if (end == std::string::npos || out.compare(end, 3, " = ") != 0) continue;
    counted += std::stoi(out.substr(at + 1, end - at - 1));
  }
  EXPECT_EQ(counted, lines) << out;
}

// The first 60 s of the real ACES log (Kuemmerle et al. 2009), written out of
// order as some CARMEN logs are: every 9th front-laser line after the two
// that follow it (~0.4 s late), one line after the next 30 (~6 s late) and
// one written twice. `localize --carmen` runs it to the end with the one
// configuration: the late lines take their place, the very late one and the
// copy are dropped, all counted and said, and the relation error is that of
// the same minute in order.
// A vehicle whose wheels are off its drawing (the left radius +0.3 %, the
// right -0.2 %, the track +1 %, three times the default wheel noise):
// `localize --mode lines --lidar --odometry-out` calibrates it against the
// LiDAR's wall lines, and a later drive of the same vehicle dead-reckons far
// better with `--odometry` than with the nominal geometry.
TEST(LocalizeOdometryCli, ALocalizedDriveCalibratesTheWheelsForTheNextDrive) {
  if (::groundline::testing::Sanitized()) {
    GTEST_SKIP() << "two LiDAR localizations of 200 m: too slow under AddressSanitizer (Debug); "
                    "the calibration itself runs under it in integration_odometry_calibration_test";
  }
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("localize_odometry");
  WriteLines(dir / "worn.yaml", {"format: groundline-sim-scenario", "version: 1.0", "zone: B",
                                 "route: {length_m: 250, closed_loop: true, "
                                 "length_tolerance_fraction: 0.2}",
                                 "encoders: {radius_scale_stddev: 0, left_radius_scale: 1.003, "
                                 "right_radius_scale: 0.998, track_scale: 1.01, "
                                 "wheel_variance_m2_per_m: 3.0e-5}"});
  std::string out;
  for (const char* seed : {"11", "12"}) {
    ASSERT_EQ(RunGroundline("sim --scenario " + Quoted(dir / "worn.yaml") + " --seed " + seed +
                                " --no-camera --out " + Quoted(dir / (std::string("d") + seed)),
                            dir, &out),
              0)
        << out;
  }
  const nlohmann::json truth = ReadJson(dir / "d11" / "vehicle_truth.json");
  ASSERT_EQ(RunGroundline("localize --dataset " + Quoted(dir / "d11") +
                              " --mode lines --lidar --odometry-out " +
                              Quoted(dir / "odometry.json") + " --out " + Quoted(dir / "cal"),
                          dir, &out),
            0)
      << out;
  EXPECT_NE(out.find("odometry calibrated from"), std::string::npos) << out;
  const nlohmann::json cal = ReadJson(dir / "odometry.json");
  ASSERT_EQ(cal["format"], "groundline-odometry-calibration");
  const char* const fields[] = {"left_wheel_radius_m", "right_wheel_radius_m", "track_m"};
  for (int i = 0; i < 3; ++i) {
    const char* field = fields[i];
    const double sigma = std::sqrt(cal["covariance_left_right_track_m2"][i][i].get<double>());
    const double error = cal[field].get<double>() - truth[field].get<double>();
    std::printf("%s: %.6f (truth %.6f, sigma %.2g)\n", field, cal[field].get<double>(),
                truth[field].get<double>(), sigma);
    EXPECT_LT(std::abs(error), 3.0 * sigma) << field;
  }
  // The radii found to better than a tenth of their error, the track to 0.6 %.
  EXPECT_NEAR(cal["left_wheel_radius_m"].get<double>(), truth["left_wheel_radius_m"].get<double>(),
              1.25e-4);
  EXPECT_NEAR(cal["right_wheel_radius_m"].get<double>(),
              truth["right_wheel_radius_m"].get<double>(), 1.25e-4);
  EXPECT_NEAR(cal["track_m"].get<double>(), truth["track_m"].get<double>(), 4.5e-3);
  // The wheel variance (3e-5; the preset assumes 1e-5) within a factor 2
  // below and 1.5 above: on the true trajectory the estimator comes out
  // 0.72-1.06 of the truth, and this drive is short (250 m).
  EXPECT_GT(cal["wheel_variance_m2_per_m"].get<double>(), 1.5e-5);
  EXPECT_LT(cal["wheel_variance_m2_per_m"].get<double>(), 4.5e-5);
  const nlohmann::json summary = ReadJson(dir / "cal" / "summary.json");
  EXPECT_EQ(summary["odometry_calibration"]["segments"], cal["segments"]);

  // The next drive, dead reckoning only: nominal against calibrated.
  std::vector<double> ate;
  for (const std::string& extra : {std::string(), " --odometry " + Quoted(dir / "odometry.json")}) {
    const std::filesystem::path run = dir / ("dr" + std::to_string(ate.size()));
    ASSERT_EQ(RunGroundline("localize --dataset " + Quoted(dir / "d12") + " --mode odometry" +
                                extra + " --out " + Quoted(run),
                            dir, &out),
              0)
        << out;
    ate.push_back(ReadJson(run / "summary.json")["accuracy"]["ate_rmse_m"].get<double>());
  }
  std::printf("next drive, dead reckoning ATE: nominal %.2f m, calibrated %.2f m\n", ate[0],
              ate[1]);
  EXPECT_LT(ate[1], 0.3 * ate[0]);

  // Errors: --odometry-out outside --mode lines; --odometry with --wheel-variance.
  EXPECT_EQ(RunGroundline("localize --dataset " + Quoted(dir / "d12") +
                              " --mode odometry --odometry-out x.json --out " + Quoted(dir / "e1"),
                          dir, &out),
            2);
  EXPECT_NE(out.find("--odometry-out"), std::string::npos) << out;
  EXPECT_EQ(RunGroundline("localize --dataset " + Quoted(dir / "d12") +
                              " --mode odometry --odometry " + Quoted(dir / "odometry.json") +
                              " --wheel-variance 1e-5 --out " + Quoted(dir / "e2"),
                          dir, &out),
            2);
  EXPECT_NE(out.find("give one or the other"), std::string::npos) << out;
}

TEST(LocalizeCarmenCli, ALogWrittenOutOfOrderRunsToTheEndAsInOrder) {
  if (::groundline::testing::Sanitized()) {
    GTEST_SKIP() << "two SLAM runs of a real minute: too slow under AddressSanitizer (Debug); the "
                    "ordering's unit tests run there";
  }
  GROUNDLINE_REQUIRE_DATA("lidar2d/aces.clf.bz2");
  GROUNDLINE_REQUIRE_DATA("lidar2d/aces.relations");
  const std::filesystem::path data = ::groundline::testing::SharedDataDir() / "lidar2d";
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("localize_carmen_order");
  constexpr double kEndS = 130.0;  // ACES' laser clock starts at 70.3 s
  const auto stamp_of = [](const std::string& line) {
    std::istringstream in(line);
    std::vector<std::string> tokens;
    for (std::string t; in >> t;) tokens.push_back(t);
    return tokens.size() >= 3 ? std::stod(tokens[tokens.size() - 3]) : 0.0;
  };
  std::vector<std::string> lines;
  std::vector<std::size_t> flaser;  // indices of the FLASER lines
  {
    core::Result<io::LineReader> reader = io::LineReader::Open(data / "aces.clf.bz2");
    ASSERT_TRUE(reader.ok()) << reader.message();
    for (std::string line; reader->ReadLine(&line);) {
      const bool is_flaser = line.rfind("FLASER ", 0) == 0;
      if (is_flaser && stamp_of(line) > kEndS) break;
      if (is_flaser) flaser.push_back(lines.size());
      lines.push_back(line);
    }
    ASSERT_TRUE(reader->status().ok()) << reader->status().message();
  }
  ASSERT_GT(flaser.size(), 250u);
  std::vector<std::string> shuffled = lines;
  const auto rotate = [&](std::size_t first, std::size_t last) {  // flaser[first] after [last]
    const std::string moved = shuffled[flaser[first]];
    for (std::size_t k = first; k < last; ++k) shuffled[flaser[k]] = shuffled[flaser[k + 1]];
    shuffled[flaser[last]] = moved;
  };
  int moved_a_little = 0;
  for (std::size_t k = 4; k + 2 < flaser.size(); k += 9) {
    if (k >= 150 && k <= 190) continue;  // leave room for the far move
    rotate(k, k + 2);
    ++moved_a_little;
  }
  rotate(160, 190);
  shuffled.insert(shuffled.begin() + static_cast<long>(flaser[100]) + 1, shuffled[flaser[100]]);
  WriteLines(dir / "in_order.clf", lines);
  WriteLines(dir / "shuffled.clf", shuffled);
  WriteAcesRelationsUpTo(data, kEndS, dir);
  const auto [in_order, in_order_out] = RunCarmen(dir, "in_order.clf", "in_order");
  const auto [reordered, reordered_out] = RunCarmen(dir, "shuffled.clf", "shuffled");
  EXPECT_EQ(in_order["scans_reordered"].get<int>(), 0);
  EXPECT_EQ(in_order["n_scans"].get<std::size_t>(), flaser.size());
  EXPECT_EQ(reordered["scans_reordered"].get<int>(), moved_a_little);
  EXPECT_EQ(reordered["scans_dropped_late"].get<int>(), 1);
  EXPECT_EQ(reordered["scans_dropped_duplicate"].get<int>(), 1);
  EXPECT_EQ(reordered["n_scans"].get<std::size_t>(), flaser.size() - 1);
  EXPECT_NE(reordered_out.find("front-laser scans written after newer ones: " +
                               std::to_string(moved_a_little) + " (first: line"),
            std::string::npos)
      << reordered_out;
  EXPECT_NE(reordered_out.find("dropped front-laser scans: 1 more than 1 s late, 1 with the "
                               "stamp of the scan before"),
            std::string::npos)
      << reordered_out;
  const double in_order_m = in_order["accuracy"]["rel_trans_mean_m"].get<double>();
  const double reordered_m = reordered["accuracy"]["rel_trans_mean_m"].get<double>();
  EXPECT_LT(in_order_m, 0.06) << in_order.dump(2);
  EXPECT_NEAR(reordered_m, in_order_m, 0.002) << reordered.dump(2);
}

// The same real minute of ACES with every front-laser line written as a
// RAWLASER1 line: the ranges and their stamp, no pose. The robot's motion is
// then only in the log's ODOM lines, which ACES writes at their own stamps
// between the laser lines. Each scan gets the odometry's pose interpolated
// at its stamp, and the relation error is that of the FLASER lines' own
// poses.
TEST(LocalizeCarmenCli, RawLaserLinesTakeTheirPosesFromTheOdomLines) {
  if (::groundline::testing::Sanitized()) {
    GTEST_SKIP() << "two SLAM runs of a real minute: too slow under AddressSanitizer (Debug); the "
                    "interpolation's unit tests run there";
  }
  GROUNDLINE_REQUIRE_DATA("lidar2d/aces.clf.bz2");
  GROUNDLINE_REQUIRE_DATA("lidar2d/aces.relations");
  const std::filesystem::path data = ::groundline::testing::SharedDataDir() / "lidar2d";
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("localize_carmen_rawlaser");
  constexpr double kEndS = 130.0;
  std::vector<std::string> flaser_log, rawlaser_log;
  int scans = 0, odom = 0;
  {
    core::Result<io::LineReader> reader = io::LineReader::Open(data / "aces.clf.bz2");
    ASSERT_TRUE(reader.ok()) << reader.message();
    for (std::string line; reader->ReadLine(&line);) {
      std::istringstream in(line);
      std::vector<std::string> t;
      for (std::string token; in >> token;) t.push_back(token);
      const bool message = !t.empty() && (t[0] == "FLASER" || t[0] == "ODOM");
      if (message && t.size() >= 3 && std::stod(t[t.size() - 3]) > kEndS) break;
      flaser_log.push_back(line);
      if (t.empty() || t[0] != "FLASER") {
        odom += !t.empty() && t[0] == "ODOM";
        rawlaser_log.push_back(line);
        continue;
      }
      // FLASER n r_1..r_n x y theta odom_x odom_y odom_theta ipc host logger
      const std::size_t n = std::stoul(t[1]);
      ASSERT_EQ(t.size(), 2 + n + 6 + 3) << line;
      std::string raw = "RAWLASER1 0 -1.5707963268 3.1415926536 0.0174532925 80.0 0.01 0 " + t[1];
      for (std::size_t i = 0; i < n; ++i) raw += " " + t[2 + i];
      raw += " 0 " + t[t.size() - 3] + " " + t[t.size() - 2] + " " + t[t.size() - 1];
      rawlaser_log.push_back(raw);
      ++scans;
    }
    ASSERT_TRUE(reader->status().ok()) << reader->status().message();
  }
  ASSERT_GT(scans, 250);
  ASSERT_GT(odom, 250);
  WriteLines(dir / "flaser.clf", flaser_log);
  WriteLines(dir / "rawlaser.clf", rawlaser_log);
  WriteAcesRelationsUpTo(data, kEndS, dir);
  const nlohmann::json flaser = RunCarmen(dir, "flaser.clf", "flaser").first;
  const nlohmann::json raw = RunCarmen(dir, "rawlaser.clf", "rawlaser").first;
  EXPECT_EQ(flaser["scans_posed_from_odom"].get<int>(), 0);
  // Every scan but those before the first ODOM line or after the last.
  const int posed = raw["scans_posed_from_odom"].get<int>();
  EXPECT_EQ(posed + raw["scans_without_odometry"].get<int>(), scans);
  EXPECT_LE(raw["scans_without_odometry"].get<int>(), 2);
  EXPECT_EQ(raw["n_scans"].get<int>(), posed);
  const double flaser_m = flaser["accuracy"]["rel_trans_mean_m"].get<double>();
  const double raw_m = raw["accuracy"]["rel_trans_mean_m"].get<double>();
  EXPECT_LT(flaser_m, 0.06) << flaser.dump(2);
  EXPECT_NEAR(raw_m, flaser_m, 0.005) << raw.dump(2);
}

}  // namespace
}  // namespace groundline
