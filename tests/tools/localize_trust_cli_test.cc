// `groundline localize` says when a run is not what it seems, through the
// executable as a user runs it: a relocalization hint the floor contradicts
// (reported, nothing committed) against the right hint (committed near the
// truth); an empty atlas from mapping (exit 1); a mean NEES far outside its
// band; streams that do not overlap; malformed CARMEN lines skipped; a
// non-finite --initial-pose refused before anything is written; an atlas
// kept current on a floor that changed.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "groundline/core/dataset.h"
#include "groundline/core/floor_map.h"
#include "groundline/core/trajectory.h"
#include "groundline/core/trajectory_association.h"
#include "groundline/core/trajectory_io.h"
#include "groundline/localization/atlas.h"
#include "groundline/localization/floor_association.h"
#include "groundline/perception/hesse_line.h"
#include "test_data.h"
#include "tools_under_test.h"

namespace groundline {
namespace {

namespace fs = std::filesystem;
using testing::Quoted;
using testing::ReadJson;
using testing::ReadText;
using testing::RunGroundline;

bool HasWarning(const nlohmann::json& summary, const std::string& kind) {
  for (const nlohmann::json& w : summary["warnings"]) {
    if (w["kind"] == kind) return true;
  }
  return false;
}

// One simulated zone A drive with the camera (60 m, 2.5 Hz) and the LiDAR: zone A's floor is
// distinctive enough to relocalize on. Simulated once and shared by the
// tests, also across processes (ctest runs each test in its own, two at a
// time): the first takes a lock and simulates, the others wait and reuse it.
// The folder is named after the executable's build, so a rebuilt simulator
// simulates afresh.
class LocalizeTrust : public ::testing::Test {
 protected:
  void SetUp() override {
    if (::groundline::testing::Sanitized()) {
      // The camera drive (150 rendered frames) and its relocalizations take
      // many minutes of a Debug executable under ASan; ~2 min in release.
      GTEST_SKIP() << "too slow under AddressSanitizer (Debug); runs in the release build";
    }
    fs::path base = fs::temp_directory_path();
    if (const char* env = std::getenv("GROUNDLINE_TEST_TMPDIR"); env != nullptr && *env != '\0') {
      base = env;
    }
    const auto built =
        fs::last_write_time(::groundline::testing::GroundlineCli()).time_since_epoch().count();
    const fs::path shared = base / ("LocalizeTrust.zone_a." + std::to_string(built));
    fs::create_directories(shared);
    dataset_ = shared / "zone_a";
    const int lock = ::open((shared / "lock").c_str(), O_CREAT | O_RDWR, 0644);
    ASSERT_GE(lock, 0);
    ::flock(lock, LOCK_EX);
    if (!fs::exists(shared / "done")) {
      // The datasets of earlier builds (160 MB each) go.
      for (const fs::directory_entry& e : fs::directory_iterator(base)) {
        const std::string name = e.path().filename().string();
        if (name.rfind("LocalizeTrust.zone_a.", 0) == 0 && e.path() != shared) {
          std::error_code ec;
          fs::remove_all(e.path(), ec);
        }
      }
      fs::remove_all(dataset_);
      std::string out;
      const int code = RunGroundline(
          "sim --zone A --length 60m --seed 3 --camera-rate 2.5 --out " + Quoted(dataset_), shared,
          &out);
      if (code == 0) std::ofstream(shared / "done") << "ok\n";
      EXPECT_EQ(code, 0) << out;
    }
    ::flock(lock, LOCK_UN);
    ::close(lock);
    ASSERT_TRUE(fs::exists(shared / "done"));
    dir_ = ::groundline::testing::ScratchDir("run");
  }
  core::Dataset Read() const {
    core::DatasetReadOptions options;
    options.check_image_files = false;
    core::Result<core::Dataset> d = core::ReadDataset(dataset_, options);
    EXPECT_TRUE(d.ok()) << d.message();
    return d.ok() ? *d : core::Dataset{};
  }
  fs::path dir_;
  fs::path dataset_;
};

std::string Hint(const Eigen::Vector2d& p) {
  return std::to_string(p.x()) + " " + std::to_string(p.y());
}

TEST_F(LocalizeTrust, WrongRelocalizationHintIsReportedAndNothingCommits) {
  const core::Dataset d = Read();
  ASSERT_TRUE(d.manifest.start_pose);
  // 20 m along the zone's x axis from the dock: floor unlike the start's.
  const Eigen::Vector2d hint =
      d.manifest.start_pose->T_map_base.translation() + Eigen::Vector2d(20.6, 0.5);
  const fs::path run = dir_ / "wrong_hint";
  std::string out;
  EXPECT_EQ(
      RunGroundline("localize --dataset " + Quoted(dataset_) +
                        " --mode lines --relocalize --near " + Hint(hint) + " --out " + Quoted(run),
                    dir_, &out),
      1)
      << out;
  EXPECT_NE(out.find("is not supported by the floor seen: the best hypothesis near it scores"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("m from the hint"), std::string::npos) << out;
  EXPECT_NE(out.find("nothing committed"), std::string::npos) << out;
  EXPECT_EQ(out.find("relocalized:"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(run / "summary.json"));
}

TEST_F(LocalizeTrust, RightRelocalizationHintCommitsNearTheTruth) {
  const core::Dataset d = Read();
  ASSERT_TRUE(d.manifest.start_pose);
  const Eigen::Vector2d hint =
      d.manifest.start_pose->T_map_base.translation() + Eigen::Vector2d(0.6, 0.5);
  const fs::path run = dir_ / "right_hint";
  std::string out;
  ASSERT_EQ(
      RunGroundline("localize --dataset " + Quoted(dataset_) +
                        " --mode lines --relocalize --near " + Hint(hint) + " --out " + Quoted(run),
                    dir_, &out),
      0)
      << out;
  const nlohmann::json summary = ReadJson(run / "summary.json");
  const nlohmann::json& r = summary["relocalized"];
  ASSERT_TRUE(r.is_object()) << summary.dump(2);
  const double stamp_s = r["stamp_s"].get<double>();
  const core::Trajectory& truth = d.ground_truth;
  const auto at = std::min_element(truth.begin(), truth.end(), [&](const auto& a, const auto& b) {
    return std::abs(a.stamp_s - stamp_s) < std::abs(b.stamp_s - stamp_s);
  });
  ASSERT_NE(at, truth.end());
  ASSERT_LT(std::abs(at->stamp_s - stamp_s), 0.02);
  EXPECT_LT(
      (Eigen::Vector2d(r["x_m"].get<double>(), r["y_m"].get<double>()) - at->pose.translation())
          .norm(),
      0.10);
  // The commit's evidence, and no ground-truth figure beside the estimate:
  // the accuracy comes after it, under its own heading.
  EXPECT_GE(r["evidence"]["matched"].get<int>(), 8);
  const std::size_t estimate = out.find("relocalized:");
  ASSERT_NE(estimate, std::string::npos) << out;
  const std::string estimate_line = out.substr(estimate, out.find('\n', estimate) - estimate);
  EXPECT_EQ(estimate_line.find("error"), std::string::npos) << estimate_line;
  const std::size_t diagnostics =
      out.find("diagnostics (ground truth, not available on a vehicle)");
  ASSERT_NE(diagnostics, std::string::npos) << out;
  EXPECT_GT(diagnostics, estimate) << out;
  EXPECT_GT(out.find("ATE RMSE"), diagnostics) << out;
}

TEST_F(LocalizeTrust, MappingAnEmptyAtlasSaysSoAndFails) {
  // One second of driving: a frame or two, no line seen twice.
  const fs::path run = dir_ / "mapping";
  std::string out;
  EXPECT_EQ(RunGroundline("localize --dataset " + Quoted(dataset_) +
                              " --mode mapping --max-duration 1 --out " + Quoted(run),
                          dir_, &out),
            1)
      << out;
  EXPECT_NE(out.find("warning: the atlas built has 0 floor lines"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(run / "atlas.json"));
  const nlohmann::json summary = ReadJson(run / "summary.json");
  EXPECT_TRUE(HasWarning(summary, "atlas_nearly_empty")) << summary.dump(2);
  EXPECT_EQ(summary["atlas_lines"].get<int>(), 0);
}

// Bounds of the mapping test, tied to four surveyed markings: measured
// 6.2 cm worst for the mapped keyframes, 9.3 mm median offset of the atlas'
// floor lines, 3.2 cm ATE on the atlas (the atlas' own error, mostly along
// the drive: docs/atlas.md, "Mapping with the LiDAR"). Anchored by the start
// pose alone the same drive mapped to 8.6 cm worst and localized to 6.2 cm
// (measured before the mapper took the localizer's odometry noise);
// the causal mapping smoother alone is 23 cm off.
constexpr double kMappedMaxErrorM = 0.09;
constexpr double kAtlasMedianM = 0.02;
constexpr double kOnAtlasAteM = 0.05;

TEST_F(LocalizeTrust, MappingWithTheLidarTiedToSurveyedMarkingsBuildsAnAtlasTheFloorLocalizesOn) {
  const fs::path run = dir_ / "mapping_lidar";
  const fs::path atlas = dir_ / "mapped_atlas.json";
  // The site's survey of a handful of markings: the four longest floor
  // markings of the floor map, stated to 3 mm per vertex.
  core::Result<core::FloorMap> floor = core::ReadFloorMap(dataset_ / "floor_map.yaml");
  ASSERT_TRUE(floor.ok()) << floor.message();
  std::vector<core::FloorMarking> markings;
  for (const core::FloorMarking& m : floor->markings) {
    if (!core::IsFaceKind(m.kind)) markings.push_back(m);
  }
  const auto length = [](const core::FloorMarking& m) {
    double l = 0.0;
    for (std::size_t i = 1; i < m.polyline_m.size(); ++i) {
      l += (m.polyline_m[i] - m.polyline_m[i - 1]).norm();
    }
    return l;
  };
  std::sort(markings.begin(), markings.end(),
            [&](const auto& a, const auto& b) { return length(a) > length(b); });
  ASSERT_GE(markings.size(), 4u);
  core::FloorMap survey;
  survey.markings.assign(markings.begin(), markings.begin() + 4);
  survey.survey = core::FloorMapSurvey();
  const fs::path survey_file = dir_ / "surveyed_markings.yaml";
  ASSERT_TRUE(core::WriteFloorMap(survey_file, survey).ok());
  std::string out;
  ASSERT_EQ(RunGroundline("localize --dataset " + Quoted(dataset_) +
                              " --mode mapping --lidar --surveyed " + Quoted(survey_file) +
                              " --atlas-out " + Quoted(atlas) + " --out " + Quoted(run),
                          dir_, &out),
            0)
      << out;
  const nlohmann::json summary = ReadJson(run / "summary.json");
  const nlohmann::json& mapping = summary["mapping"];
  EXPECT_GT(mapping["scans"].get<int>(), 500) << mapping.dump(2);
  EXPECT_GE(mapping["floor_lines"].get<int>(), 4) << mapping.dump(2);
  EXPECT_GE(mapping["faces"].get<int>(), 1) << mapping.dump(2);
  EXPECT_TRUE(mapping["covariances"].get<bool>());
  EXPECT_GE(mapping["surveyed_matched"].get<int>(), 2) << mapping.dump(2);
  EXPECT_EQ(mapping["surveyed_ambiguous"].get<int>(), 0) << mapping.dump(2);
  // The mapped keyframes against the truth (the survey and the start pose
  // anchor them).
  core::Result<core::Trajectory> mapped = core::ReadTumTrajectory(run / "trajectory_mapped.tum");
  ASSERT_TRUE(mapped.ok()) << mapped.message();
  core::Result<core::Dataset> dataset = core::ReadDataset(dataset_.string());
  ASSERT_TRUE(dataset.ok()) << dataset.message();
  double worst_m = 0.0;
  for (const core::StampedPose& p : *mapped) {
    worst_m =
        std::max(worst_m, (p.pose.translation() -
                           core::InterpolatePose(dataset->ground_truth, p.stamp_s).translation())
                              .norm());
  }
  EXPECT_LT(worst_m, kMappedMaxErrorM);
  // The atlas against the floor map, landmark by landmark.
  ASSERT_EQ(RunGroundline("eval --dataset " + Quoted(dataset_) + " --atlas " + Quoted(atlas) +
                              " --json " + Quoted(dir_ / "atlas_accuracy.json"),
                          dir_, &out),
            0)
      << out;
  const nlohmann::json accuracy = ReadJson(dir_ / "atlas_accuracy.json");
  EXPECT_GE(accuracy["floor lines"]["paired"].get<int>(), 4) << accuracy.dump(2);
  EXPECT_LT(accuracy["floor lines"]["median_abs_rho_m"].get<double>(), kAtlasMedianM)
      << accuracy.dump(2);
  // The drive localized on its own atlas, nothing taken from the floor map.
  const fs::path on_atlas = dir_ / "on_mapped_atlas";
  ASSERT_EQ(
      RunGroundline("localize --dataset " + Quoted(dataset_) + " --mode lines --lidar --atlas " +
                        Quoted(atlas) + " --out " + Quoted(on_atlas),
                    dir_, &out),
      0)
      << out;
  EXPECT_NE(out.find("from " + atlas.string()), std::string::npos) << out;
  const nlohmann::json localized = ReadJson(on_atlas / "summary.json");
  EXPECT_LT(localized["accuracy"]["ate_rmse_m"].get<double>(), kOnAtlasAteM) << localized.dump(2);

  // Surveyed landmarks only anchor a mapping drive with the LiDAR.
  EXPECT_NE(RunGroundline("localize --dataset " + Quoted(dataset_) + " --mode lines --surveyed " +
                              Quoted(survey_file) + " --out " + Quoted(dir_ / "not_mapping"),
                          dir_, &out),
            0);
  EXPECT_NE(out.find(survey_file.string() + ": surveyed landmarks anchor a mapping run"),
            std::string::npos)
      << out;
}

// How many of the drive's poses see at least 1 m of the marking well inside
// the camera's view (0.8-2.1 m ahead, 0.8 m either side).
int PosesSeeing(const core::FloorMarking& marking, const core::Trajectory& truth) {
  int poses = 0;
  for (std::size_t k = 0; k < truth.size(); k += 5) {
    const core::SE2 T_base_map = truth[k].pose.Inverse();
    double inside_m = 0.0;
    for (std::size_t i = 1; i < marking.polyline_m.size(); ++i) {
      const Eigen::Vector2d a = T_base_map * marking.polyline_m[i - 1];
      const Eigen::Vector2d b = T_base_map * marking.polyline_m[i];
      for (int j = 0; j < 100; ++j) {
        const Eigen::Vector2d p = a + (j + 0.5) / 100.0 * (b - a);
        if (p.x() > 0.8 && p.x() < 2.1 && std::abs(p.y()) < 0.8) inside_m += (b - a).norm() / 100;
      }
    }
    poses += inside_m >= 1.0 ? 1 : 0;
  }
  return poses;
}

// The atlas was made before a marking was laid, and lists one that has since
// been taken up. Localizing with --atlas-out keeps it current: the one taken
// up is retired, the one laid is born where the floor has it.
TEST_F(LocalizeTrust, KeepingTheAtlasCurrentRetiresAMarkingTheFloorLacksAndMapsOneItGained) {
  const core::Dataset d = Read();
  ASSERT_FALSE(d.ground_truth.empty());
  ASSERT_TRUE(d.floor_map);
  const localization::Atlas truth =
      localization::AtlasFromFloorMap(*d.floor_map, localization::AtlasFromFloorMapOptions());
  const auto angle = [](const localization::AtlasLine& a, const localization::AtlasLine& b) {
    return std::abs(perception::LineDifference(a.line_map, b.line_map)(1));
  };
  // The offset of the floor's line t from the middle of the line `built`.
  const auto offset_at_middle = [](const localization::AtlasLine& built,
                                   const localization::AtlasLine& t) {
    const Eigen::Vector2d middle = 0.5 * (built.endpoint_a_m + built.endpoint_b_m);
    return std::abs(t.line_map.Normal().dot(middle) - t.line_map.rho_m);
  };
  const auto lines_of = [](const core::FloorMarking& m) {
    return localization::AtlasFromFloorMap(core::FloorMap{"map", {m}, std::nullopt},
                                           localization::AtlasFromFloorMapOptions());
  };
  // Candidates: straight floor markings that lie on no other marking (a
  // joint under a tape is one line to the camera).
  std::vector<std::pair<int, std::size_t>> seen;
  for (std::size_t i = 0; i < d.floor_map->markings.size(); ++i) {
    const core::FloorMarking& m = d.floor_map->markings[i];
    if (core::IsFaceKind(m.kind) || m.polyline_m.size() != 2) continue;
    const int poses = PosesSeeing(m, d.ground_truth);
    if (poses < 20) continue;
    const localization::AtlasLine line = lines_of(m).lines.front();
    int on_it = 0;
    for (const localization::AtlasLine& t : truth.lines) {
      on_it += angle(line, t) < 0.02 && offset_at_middle(line, t) < 0.05 &&
               localization::ExtentsOverlap(line, t, 0.0);
    }
    if (on_it == 1) seen.push_back({poses, i});
  }
  std::sort(seen.rbegin(), seen.rend());
  ASSERT_GE(seen.size(), 2u) << "the drive sees too little of its markings";
  // Laid after the survey: the marking seen longest. Taken up: a copy of the
  // next one 0.5 m aside, towards the drive (it is not on the floor).
  const core::FloorMarking laid = d.floor_map->markings[seen[0].second];
  core::FloorMarking taken_up = d.floor_map->markings[seen[1].second];
  {
    const Eigen::Vector2d a = taken_up.polyline_m[0], b = taken_up.polyline_m[1];
    const Eigen::Vector2d along = (b - a).normalized();
    Eigen::Vector2d normal(-along.y(), along.x());
    const Eigen::Vector2d middle = 0.5 * (a + b);
    const auto nearest = std::min_element(
        d.ground_truth.begin(), d.ground_truth.end(), [&](const auto& p, const auto& q) {
          return (p.pose.translation() - middle).norm() < (q.pose.translation() - middle).norm();
        });
    if (normal.dot(nearest->pose.translation() - middle) < 0.0) normal = -normal;
    for (Eigen::Vector2d& p : taken_up.polyline_m) p += 0.5 * normal;
    for (const core::FloorMarking& m : d.floor_map->markings) {
      taken_up.id = std::max(taken_up.id, m.id + 1);
    }
  }
  std::printf("laid: marking %lld (%s, seen from %d poses); taken up: a copy of marking %lld "
              "moved to (%.2f, %.2f)-(%.2f, %.2f)\n",
              static_cast<long long>(laid.id), std::string(core::MarkingKindName(laid.kind)).c_str(),
              seen[0].first, static_cast<long long>(d.floor_map->markings[seen[1].second].id),
              taken_up.polyline_m[0].x(), taken_up.polyline_m[0].y(), taken_up.polyline_m[1].x(),
              taken_up.polyline_m[1].y());
  core::FloorMap surveyed = *d.floor_map;
  std::erase_if(surveyed.markings, [&](const core::FloorMarking& m) { return m.id == laid.id; });
  surveyed.markings.push_back(taken_up);
  const localization::Atlas stale =
      localization::AtlasFromFloorMap(surveyed, localization::AtlasFromFloorMapOptions());
  const fs::path stale_file = dir_ / "stale_atlas.json";
  const fs::path kept_file = dir_ / "kept_atlas.json";
  ASSERT_TRUE(localization::WriteAtlas(stale_file, stale).ok());

  const fs::path run = dir_ / "kept";
  std::string out;
  ASSERT_EQ(RunGroundline("localize --dataset " + Quoted(dataset_) + " --mode lines --atlas " +
                              Quoted(stale_file) + " --atlas-out " + Quoted(kept_file) + " --out " +
                              Quoted(run),
                          dir_, &out),
            0)
      << out;
  EXPECT_NE(out.find("atlas kept current: "), std::string::npos) << out;
  const nlohmann::json summary = ReadJson(run / "summary.json");
  const nlohmann::json& upkeep = summary["upkeep"];
  EXPECT_GE(upkeep["landmarks_born"].get<int>(), 1) << upkeep.dump();
  EXPECT_GE(upkeep["landmarks_retired"].get<int>(), 1) << upkeep.dump();
  const core::Result<localization::Atlas> kept = localization::ReadAtlas(kept_file);
  ASSERT_TRUE(kept.ok()) << kept.message();
  EXPECT_EQ(kept->lines.size() + kept->junctions.size(),
            stale.lines.size() + stale.junctions.size() + upkeep["landmarks_born"].get<int>() -
                upkeep["landmarks_retired"].get<int>());

  // The marking taken up is gone; every other surveyed line is kept.
  const localization::Atlas taken_up_lines = lines_of(taken_up);
  const auto same = [](const localization::AtlasLine& a, const localization::AtlasLine& b) {
    const Eigen::Vector2d diff = perception::LineDifference(a.line_map, b.line_map);
    return std::abs(diff(0)) < 1e-6 && std::abs(diff(1)) < 1e-6 &&
           localization::ExtentsOverlap(a, b, 0.0);
  };
  for (const localization::AtlasLine& s : stale.lines) {
    bool is_taken_up = false;
    for (const localization::AtlasLine& t : taken_up_lines.lines) is_taken_up |= same(s, t);
    bool is_kept = false;
    for (const localization::AtlasLine& k : kept->lines) is_kept |= k.id == s.id;
    EXPECT_EQ(is_kept, !is_taken_up) << "line " << s.id;
  }
  // The laid one is born, within 1.5 cm and 0.3 deg of the floor's, measured
  // at the born line's middle; nothing born is off the floor's lines.
  const localization::Atlas laid_lines = lines_of(laid);
  int born_on_laid = 0;
  for (const localization::AtlasLine& k : kept->lines) {
    if (!k.seen) continue;  // surveyed
    double best = 1e9;
    for (const localization::AtlasLine& t : truth.lines) {
      if (angle(k, t) < 0.01 && localization::ExtentsOverlap(k, t, 0.0)) {
        best = std::min(best, offset_at_middle(k, t));
      }
    }
    EXPECT_LT(best, 0.05) << "born line " << k.id << " lies on no marking of the floor";
    for (const localization::AtlasLine& t : laid_lines.lines) {
      if (localization::ExtentsOverlap(k, t, 0.0) && offset_at_middle(k, t) < 0.015 &&
          angle(k, t) < 0.3 * M_PI / 180.0) {
        ++born_on_laid;
      }
    }
  }
  EXPECT_GE(born_on_laid, 1) << "the marking laid was not born";

  // Only the modes that make or keep an atlas write one.
  EXPECT_EQ(RunGroundline("localize --dataset " + Quoted(dataset_) + " --atlas-out " +
                              Quoted(dir_ / "odometry_atlas.json") + " --out " +
                              Quoted(dir_ / "odometry"),
                          dir_, &out),
            2);
  EXPECT_NE(out.find("an atlas is written by --mode mapping"), std::string::npos) << out;
}

TEST_F(LocalizeTrust, NeesFarOutsideItsBandWarns) {
  // Odometry noise overridden a thousand times too small: the covariances
  // understate the errors.
  const fs::path run = dir_ / "nees";
  std::string out;
  ASSERT_EQ(RunGroundline("localize --dataset " + Quoted(dataset_) +
                              " --mode lines --wheel-variance 1e-9 --lateral-variance 1e-12 "
                              "--out " +
                              Quoted(run),
                          dir_, &out),
            0)
      << out;
  EXPECT_NE(out.find("warning: the mean NEES against ground truth is"), std::string::npos) << out;
  const nlohmann::json summary = ReadJson(run / "summary.json");
  EXPECT_GT(summary["accuracy"]["nees_mean"].get<double>(), 30.0);
  EXPECT_TRUE(HasWarning(summary, "nees_out_of_band")) << summary.dump(2);

  // The preset's noise on the same drive: no warning.
  const fs::path plain = dir_ / "nees_preset";
  ASSERT_EQ(RunGroundline(
                "localize --dataset " + Quoted(dataset_) + " --mode lines --out " + Quoted(plain),
                dir_, &out),
            0)
      << out;
  const nlohmann::json preset = ReadJson(plain / "summary.json");
  EXPECT_LT(preset["accuracy"]["nees_mean"].get<double>(), 30.0);
  EXPECT_TRUE(preset["warnings"].empty()) << preset.dump(2);
}

TEST_F(LocalizeTrust, StreamsThatDoNotOverlapWarn) {
  // The same dataset with its odometry cut at half time (the other files
  // linked, not copied).
  const fs::path cut = dir_ / "zone_a_cut";
  fs::remove_all(cut);
  fs::create_directories(cut);
  for (const fs::directory_entry& e : fs::directory_iterator(dataset_)) {
    if (e.path().filename() == "wheel_encoders.csv") continue;
    fs::create_symlink(e.path(), cut / e.path().filename());
  }
  {
    std::ifstream in(dataset_ / "wheel_encoders.csv");
    std::ofstream half(cut / "wheel_encoders.csv");
    std::string line;
    std::vector<std::string> lines;
    while (std::getline(in, line)) lines.push_back(line);
    for (std::size_t i = 0; i < lines.size() / 2; ++i) half << lines[i] << "\n";
  }
  const fs::path run = dir_ / "cut";
  std::string out;
  ASSERT_EQ(
      RunGroundline("localize --dataset " + Quoted(cut) + " --mode lines --out " + Quoted(run),
                    dir_, &out),
      0)
      << out;
  EXPECT_NE(out.find("the wheel encoders end"), std::string::npos) << out;
  EXPECT_NE(out.find("s before the camera frames"), std::string::npos) << out;
  EXPECT_TRUE(HasWarning(ReadJson(run / "summary.json"), "stream_spans"));
}

TEST_F(LocalizeTrust, NonFiniteInitialPoseIsRefusedBeforeAnythingIsWritten) {
  const fs::path run = dir_ / "nan_pose";
  std::string out;
  EXPECT_EQ(RunGroundline("localize --dataset " + Quoted(dataset_) +
                              " --initial-pose 1 2 nan --out " + Quoted(run),
                          dir_, &out),
            2)
      << out;
  EXPECT_NE(out.find("--initial-pose: expected X_M Y_M YAW_DEG"), std::string::npos) << out;
  EXPECT_NE(out.find("yaw finite in [-360, 360] deg; got 1 2 nan"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(run));
  EXPECT_EQ(RunGroundline("localize --dataset " + Quoted(dataset_) +
                              " --mode lines --relocalize --near 1 inf --out " + Quoted(run),
                          dir_, &out),
            2)
      << out;
  EXPECT_NE(out.find("--near: expected X_M Y_M [RADIUS_M]"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(run));
}

// A small CARMEN log: a robot standing in a 6 m x 4 m room, 60 front-laser
// scans, with two malformed lines among them.
TEST(LocalizeCarmenCli, SkippedMalformedLinesAreSaidAndCounted) {
  const fs::path dir = ::groundline::testing::ScratchDir("localize_carmen_skips");
  const fs::path log = dir / "room.clf";
  {
    std::ofstream out(log);
    constexpr int kBeams = 181;
    for (int i = 0; i < 60; ++i) {
      if (i == 20) out << "FLASER 3 1.0 2.0\n";
      if (i == 40) out << "FLASER 181 not-a-number\n";
      out << "FLASER " << kBeams;
      for (int k = 0; k < kBeams; ++k) {
        const double angle = -M_PI / 2 + M_PI * k / (kBeams - 1);
        const double c = std::cos(angle), s = std::sin(angle);
        // Walls at x = 3 and y = +-2 around the robot at the origin.
        double range = 50.0;
        if (c > 1e-9) range = std::min(range, 3.0 / c);
        if (std::abs(s) > 1e-9) range = std::min(range, 2.0 / std::abs(s));
        out << ' ' << range;
      }
      const double t = 0.1 * i;
      out << " 0 0 0 0 0 0 " << t << " host " << t << "\n";
    }
  }
  const fs::path run = dir / "run";
  std::string out;
  ASSERT_EQ(RunGroundline("localize --carmen " + Quoted(log) + " --out " + Quoted(run), dir, &out),
            0)
      << out;
  EXPECT_NE(out.find("warning: " + log.string() + ": skipped 2 malformed lines (first: line 21"),
            std::string::npos)
      << out;
  const nlohmann::json summary = ReadJson(run / "summary.json");
  EXPECT_EQ(summary["lines_skipped"].get<int>(), 2);
  EXPECT_TRUE(HasWarning(summary, "skipped_lines")) << summary.dump(2);
  EXPECT_EQ(summary["n_scans"].get<int>(), 60);
}

// The camera mount's self-calibration on the rendered drive, whose mount is
// the commissioned one throughout: the estimate stays near it (tolerances
// three times what the 48 s drive gave when the test was written: pitch
// 0.04 to 0.07 deg, roll 0.01 deg, height 2.0 to 2.4 mm, yaw 0.06 to 0.1 deg
// over the estimator's revisions), raises no alarm,
// every keyframe reports it, and `calibrate history` plots it against the
// simulation's truth, which lies within 3 sigma of most keyframes.
TEST_F(LocalizeTrust, SelfCalibrationEstimatesTheMountAndHistoryPlotsIt) {
  const fs::path run = dir_ / "self_calibrate";
  std::string out;
  ASSERT_EQ(RunGroundline("localize --dataset " + Quoted(dataset_) +
                              " --mode lines --self-calibrate --out " + Quoted(run),
                          dir_, &out),
            0)
      << out;
  EXPECT_NE(out.find("self-calibration: pitch"), std::string::npos) << out;
  const nlohmann::json e = ReadJson(run / "summary.json")["self_calibration"];
  ASSERT_TRUE(e.is_object()) << out;
  EXPECT_GE(e["selfcal_windows"].get<int>(), 5);
  EXPECT_FALSE(e["selfcal_alarm"].get<bool>()) << e.dump(2);
  EXPECT_NEAR(e["selfcal_pitch_deg"].get<double>(), 42.4, 0.2);
  EXPECT_NEAR(e["selfcal_roll_deg"].get<double>(), 0.0, 0.2);
  EXPECT_NEAR(e["selfcal_height_m"].get<double>(), 0.58, 0.007);
  EXPECT_NEAR(e["selfcal_yaw_deg"].get<double>(), 0.0, 0.3);
  std::ifstream health(run / "health.jsonl");
  std::string line;
  int lines = 0;
  while (std::getline(health, line)) {
    ++lines;
    const nlohmann::json j = nlohmann::json::parse(line);
    EXPECT_TRUE(j.contains("selfcal_height_sigma_m")) << line;
    EXPECT_TRUE(j.contains("selfcal_observed_height_m")) << line;
  }
  EXPECT_GT(lines, 100);

  ASSERT_EQ(RunGroundline("calibrate history " + Quoted(run) + " --truth " +
                              Quoted(dataset_ / "ground_truth_extrinsics.csv"),
                          dir_, &out),
            0)
      << out;
  EXPECT_NE(out.find("no alarm"), std::string::npos) << out;
  const nlohmann::json errors = ReadJson(run / "self_calibration.json")["errors_against_truth"];
  for (const char* c : {"pitch", "roll", "height"}) {
    EXPECT_GE(errors[std::string(c) + "_within_3_sigma"].get<double>(), 0.9) << c << out;
  }
  const std::string html = ReadText(run / "self_calibration.html");
  EXPECT_NE(html.find("data-component='height'"), std::string::npos);
  EXPECT_NE(html.find("class='truth'"), std::string::npos);
  EXPECT_NE(html.find("class='applied'"), std::string::npos);   // the BEV's mount
  EXPECT_NE(html.find("class='observed'"), std::string::npos);  // the lines' mount
  // Without selfcal fields: an error that says what to do.
  ASSERT_EQ(RunGroundline("localize --dataset " + Quoted(dataset_) + " --mode lines --out " +
                              Quoted(dir_ / "plain_run"),
                          dir_, &out),
            0)
      << out;
  EXPECT_EQ(RunGroundline("calibrate history " + Quoted(dir_ / "plain_run"), dir_, &out), 1);
  EXPECT_NE(out.find("--self-calibrate"), std::string::npos) << out;
}

}  // namespace
}  // namespace groundline
