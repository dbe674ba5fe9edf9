// Floor-line localization end to end on simulated zone drives (observations
// generated from the floor map at the true poses, with their stated noise;
// not the extractor): localization on a surveyed atlas against the
// odometry-only baseline, NEES consistency, mapping an atlas, saving it,
// then localizing on the saved file, and keeping an atlas current while
// localizing on a floor that changed since it was made.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <set>

#include "floor_localization_run.h"
#include "groundline/localization/atlas.h"
#include "groundline/perception/hesse_line.h"

namespace groundline::localization {
namespace {

using testing::MakeZoneDrive;
using testing::RunErrors;
using testing::RunSmoother;

SmootherOptions ShortWindow(SmootherMode mode) {
  SmootherOptions options;
  options.mode = mode;
  options.window_s = 5.0;  // exercises marginalization within a short drive
  options.max_iterations = 5;
  return options;
}

void Print(const char* name, const RunErrors& e) {
  std::printf(
      "%s: %d keyframes, window <= %d, lines used %d rejected %d, junctions used %d, landmarks "
      "added %d; fused RMS %.4f m max %.4f m, "
      "along-track RMS %.4f m; odometry RMS %.4f m, along-track max %.4f m; NEES<=11.34 share "
      "%.3f\n",
      name, e.keyframes, e.max_window, e.lines_used, e.lines_rejected, e.junctions_used,
      e.landmarks_added, RunErrors::Rms(e.position_m), RunErrors::Max(e.position_m),
      RunErrors::Rms(e.along_track_m), RunErrors::Rms(e.odometry_position_m),
      RunErrors::Max(e.odometry_along_track_m), e.NeesShare(11.34));
}

TEST(FloorLocalization, ZoneBFusedIsMuchBetterThanOdometryAlongTrack) {
  const auto drive = MakeZoneDrive(sim::Zone::kB, 5, 25.0);
  const sim::FloorDriveOptions options = testing::TestDriveOptions(5);
  SlidingWindowSmoother smoother(ShortWindow(SmootherMode::kLocalization),
                                 AtlasFromFloorMap(drive.map, AtlasFromFloorMapOptions()));
  const RunErrors errors = RunSmoother(drive, options, &smoother);
  Print("zone B", errors);
  ASSERT_GT(errors.keyframes, 100);
  EXPECT_LT(RunErrors::Rms(errors.position_m), 0.02);
  EXPECT_LT(RunErrors::Rms(errors.along_track_m),
            0.25 * RunErrors::Rms(errors.odometry_along_track_m));
  EXPECT_LT(errors.max_window, 100);         // 5 s of keyframes: marginalization keeps it bounded
  EXPECT_GT(errors.NeesShare(11.34), 0.85);  // chi-square 3 dof, 0.99
}

TEST(FloorLocalization, ZoneDFusedIsMuchBetterThanOdometryAlongTrack) {
  const auto drive = MakeZoneDrive(sim::Zone::kD, 6, 25.0);
  const sim::FloorDriveOptions options = testing::TestDriveOptions(6);
  SlidingWindowSmoother smoother(ShortWindow(SmootherMode::kLocalization),
                                 AtlasFromFloorMap(drive.map, AtlasFromFloorMapOptions()));
  const RunErrors errors = RunSmoother(drive, options, &smoother);
  Print("zone D", errors);
  EXPECT_LT(RunErrors::Rms(errors.position_m), 0.05);
  EXPECT_LT(RunErrors::Rms(errors.along_track_m),
            0.5 * RunErrors::Rms(errors.odometry_along_track_m));
  EXPECT_GT(errors.NeesShare(11.34), 0.8);
}

TEST(FloorLocalization, MapThenLocalizeOnTheSavedAtlas) {
  const auto drive = MakeZoneDrive(sim::Zone::kB, 7, 25.0);
  // A surveying drive: calibrated odometry (no scale errors, 10x less noise).
  sim::FloorDriveOptions options = testing::TestDriveOptions(7);
  options.distance_scale_error = 0.0;
  options.rotation_scale_error = 0.0;
  options.noise = OdometryNoiseFromWheelVariance(1e-6, 0.760, 1e-7);
  SlidingWindowSmoother mapper(ShortWindow(SmootherMode::kMapping), Atlas());
  const RunErrors mapping = RunSmoother(drive, options, &mapper);
  Print("mapping", mapping);
  const Atlas atlas = mapper.CurrentAtlas();
  ASSERT_GT(atlas.lines.size(), 5u);
  // A 25 s mapping drive has no loop closure: the atlas can only be as good as
  // the drive (measured on this seeded route: 6.5 cm RMS, odometry 7.7 cm).
  // The invariant: mapping does not make the surveying drive worse.
  EXPECT_LT(RunErrors::Rms(mapping.position_m), RunErrors::Rms(mapping.odometry_position_m));
  EXPECT_LT(RunErrors::Rms(mapping.position_m), 0.08);
  const std::filesystem::path path =
      std::filesystem::path(::testing::TempDir()) / "floor_localization_atlas.json";
  ASSERT_TRUE(WriteAtlas(path, atlas).ok());
  const auto loaded = ReadAtlas(path);
  ASSERT_TRUE(loaded.ok()) << loaded.message();
  ASSERT_EQ(loaded->lines.size(), atlas.lines.size());

  options = testing::TestDriveOptions(8);  // an ordinary drive on the same route
  SlidingWindowSmoother localizer(ShortWindow(SmootherMode::kLocalization), *loaded);
  const RunErrors localized = RunSmoother(drive, options, &localizer);
  Print("localizing on the mapped atlas", localized);
  // The atlas carries the mapping drive's pose errors, so localizing on it is
  // bounded by them (plus a little), not by the localizing drive's noise.
  EXPECT_LT(RunErrors::Rms(localized.position_m), RunErrors::Rms(mapping.position_m) + 0.02);
  EXPECT_LT(RunErrors::Rms(localized.along_track_m),
            0.5 * RunErrors::Rms(localized.odometry_along_track_m));
}

// True if the two lines are one within rho_m and alpha_rad and their extents overlap.
bool SameLine(const AtlasLine& a, const AtlasLine& b, double rho_m, double alpha_rad) {
  const Eigen::Vector2d d = perception::LineDifference(a.line_map, b.line_map);
  return std::abs(d(0)) < rho_m && std::abs(d(1)) < alpha_rad && ExtentsOverlap(a, b, 0.0);
}

double NearestJunction(const Atlas& atlas, const Eigen::Vector2d& point_m) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const AtlasJunction& j : atlas.junctions) {
    nearest = std::min(nearest, (j.point_m - point_m).norm());
  }
  return nearest;
}

// The atlas lines of one marking.
std::vector<AtlasLine> LinesOf(const core::FloorMarking& marking) {
  core::FloorMap one;
  one.markings = {marking};
  return AtlasFromFloorMap(one, AtlasFromFloorMapOptions()).lines;
}

// How many of the drive's poses (every 10th) see at least 1 m of the marking
// well inside the camera's view box.
int TimesInView(const core::FloorMarking& marking, const core::Trajectory& trajectory,
                const sim::FloorObservationOptions& view_box) {
  FloorView view;
  view.polygon_base_m = {{view_box.min_ahead_m, -view_box.half_width_m},
                         {view_box.max_ahead_m, -view_box.half_width_m},
                         {view_box.max_ahead_m, view_box.half_width_m},
                         {view_box.min_ahead_m, view_box.half_width_m}};
  int times = 0;
  for (size_t k = 0; k < trajectory.size(); k += 10) {
    const core::SE2 T_base_map = trajectory[k].pose.Inverse();
    double inside_m = 0.0;
    for (size_t i = 0; i + 1 < marking.polyline_m.size(); ++i) {
      const Eigen::Vector2d a = T_base_map * marking.polyline_m[i];
      const Eigen::Vector2d b = T_base_map * marking.polyline_m[i + 1];
      for (int j = 0; j < 50; ++j) {
        const Eigen::Vector2d p = a + (j + 0.5) / 50.0 * (b - a);
        if (view.InsideDistance(p) > 0.2) inside_m += (b - a).norm() / 50.0;
      }
    }
    times += inside_m >= 1.0 ? 1 : 0;
  }
  return times;
}

// The floor was surveyed; since then one tape was laid (not in the atlas),
// one was taken up (in the atlas, not on the floor) and one was re-painted
// 12 cm aside. Localizing with the upkeep on retires the two the floor lost,
// maps the two new ones where they are, and leaves the rest alone; a second
// drive on the saved atlas then changes nothing (its size stays put).
TEST(FloorLocalization, AChangedFloorRetiresTheMarkingsItLostAndMapsTheNewOnes) {
  const auto drive = MakeZoneDrive(sim::Zone::kB, 9, 60.0);
  ASSERT_GT(drive.trajectory.size(), 100u);
  const sim::FloorDriveOptions drive_options = testing::TestDriveOptions(9);
  // The floor markings the drive sees longest, most seen first.
  std::vector<std::pair<int, size_t>> seen;
  for (size_t i = 0; i < drive.map.markings.size(); ++i) {
    const core::FloorMarking& m = drive.map.markings[i];
    if (core::IsFaceKind(m.kind) || m.polyline_m.size() != 2) continue;
    seen.push_back({TimesInView(m, drive.trajectory, drive_options.observations), i});
  }
  std::sort(seen.rbegin(), seen.rend());
  ASSERT_GE(seen.size(), 4u);
  ASSERT_GE(seen[3].first, 20) << "the drive sees too little of its fourth marking";
  // The two aisles' tapes: the one seen longest and its partner across the
  // aisle (the nearest of the next three), and one of the other aisle.
  const size_t taken_up = seen[0].second;
  const core::FloorMarking& first = drive.map.markings[taken_up];
  const Eigen::Vector2d first_normal =
      Eigen::Vector2d(first.polyline_m[1] - first.polyline_m[0]).normalized();
  const auto across_first = [&](const core::FloorMarking& m) {
    const Eigen::Vector2d d = 0.5 * (m.polyline_m[0] + m.polyline_m[1]) - first.polyline_m[0];
    return std::abs(first_normal.x() * d.y() - first_normal.y() * d.x());
  };
  std::vector<size_t> others = {seen[1].second, seen[2].second, seen[3].second};
  std::sort(others.begin(), others.end(), [&](size_t a, size_t b) {
    return across_first(drive.map.markings[a]) < across_first(drive.map.markings[b]);
  });
  const size_t partner = others[0], repainted = others[1];

  core::FloorMap surveyed = drive.map;  // what the atlas was made from
  core::FloorMap floor = drive.map;     // what the camera sees now
  floor.markings[taken_up].polyline_m.clear();
  {
    core::FloorMarking& m = floor.markings[repainted];
    const Eigen::Vector2d along = (m.polyline_m[1] - m.polyline_m[0]).normalized();
    for (Eigen::Vector2d& p : m.polyline_m) p += 0.12 * Eigen::Vector2d(-along.y(), along.x());
  }
  {
    // A new lane line laid 0.5 m in from the partner, towards the drive.
    core::FloorMarking laid = drive.map.markings[partner];
    for (const core::FloorMarking& m : drive.map.markings) laid.id = std::max(laid.id, m.id + 1);
    const Eigen::Vector2d middle = 0.5 * (laid.polyline_m[0] + laid.polyline_m[1]);
    const Eigen::Vector2d along = (laid.polyline_m[1] - laid.polyline_m[0]).normalized();
    Eigen::Vector2d normal(-along.y(), along.x());
    const auto nearest = std::min_element(
        drive.trajectory.begin(), drive.trajectory.end(),
        [&](const core::StampedPose& a, const core::StampedPose& b) {
          return (a.pose.translation() - middle).norm() < (b.pose.translation() - middle).norm();
        });
    if (normal.dot(nearest->pose.translation() - middle) < 0.0) normal = -normal;
    for (Eigen::Vector2d& p : laid.polyline_m) p += 0.5 * normal;
    floor.markings.push_back(laid);
  }
  const auto without_empty = [](core::FloorMap map) {
    std::erase_if(map.markings, [](const core::FloorMarking& m) { return m.polyline_m.empty(); });
    return map;
  };
  surveyed = without_empty(surveyed);
  floor = without_empty(floor);
  const Atlas before = AtlasFromFloorMap(surveyed, AtlasFromFloorMapOptions());
  const Atlas truth = AtlasFromFloorMap(floor, AtlasFromFloorMapOptions());
  std::vector<AtlasLine> gone = LinesOf(drive.map.markings[taken_up]);
  for (const AtlasLine& l : LinesOf(drive.map.markings[repainted])) gone.push_back(l);
  std::vector<AtlasLine> new_lines;  // the laid and the re-painted markings' lines
  for (const AtlasLine& t : truth.lines) {
    bool in_before = false;
    for (const AtlasLine& b : before.lines) in_before = in_before || SameLine(t, b, 1e-3, 1e-3);
    if (!in_before) new_lines.push_back(t);
  }
  ASSERT_GE(new_lines.size(), 2u);

  SmootherOptions options = ShortWindow(SmootherMode::kLocalization);
  const testing::ZoneDrive changed{floor, drive.trajectory};
  // The references: the same drive on the stale atlas, and on the floor as it is now.
  SlidingWindowSmoother on_stale(options, before);
  const RunErrors stale = RunSmoother(changed, drive_options, &on_stale);
  Print("on the stale atlas", stale);
  SlidingWindowSmoother on_truth(options, truth);
  const RunErrors exact = RunSmoother(changed, drive_options, &on_truth);
  Print("on the floor as it is", exact);

  options.upkeep.enabled = true;
  SlidingWindowSmoother localizer(options, before);
  const RunErrors errors = RunSmoother(changed, drive_options, &localizer);
  Print("localizing on a changed floor, keeping the atlas current", errors);
  EXPECT_LT(RunErrors::Rms(errors.position_m), RunErrors::Rms(exact.position_m) + 0.003);
  EXPECT_LT(RunErrors::Rms(errors.position_m), 0.5 * RunErrors::Rms(stale.position_m));
  EXPECT_GT(errors.NeesShare(11.34), 0.9);
  const Atlas after = localizer.CurrentAtlas();
  std::printf(
      "upkeep: %d landmarks born, %d retired; atlas %zu -> %zu lines, %zu -> %zu junctions\n",
      localizer.LandmarksBorn(), localizer.LandmarksRetired(), before.lines.size(),
      after.lines.size(), before.junctions.size(), after.junctions.size());

  // Retired: exactly the lines of the two markings the floor lost, and only
  // junctions that are no longer on the floor.
  std::set<std::int64_t> kept_ids;
  for (const AtlasLine& l : after.lines) kept_ids.insert(l.id);
  for (const AtlasLine& b : before.lines) {
    bool is_gone = false;
    for (const AtlasLine& g : gone) is_gone = is_gone || SameLine(b, g, 1e-3, 1e-3);
    EXPECT_EQ(kept_ids.count(b.id), is_gone ? 0u : 1u)
        << "line " << b.id
        << (is_gone ? " is gone from the floor but was kept" : " is on the floor but was retired");
  }
  std::set<std::int64_t> kept_junctions;
  for (const AtlasJunction& j : after.junctions) kept_junctions.insert(j.id);
  for (const AtlasJunction& b : before.junctions) {
    if (kept_junctions.count(b.id) > 0) continue;
    EXPECT_GT(NearestJunction(truth, b.point_m), 0.02)
        << "junction " << b.id << " is on the floor but was retired";
  }
  std::set<std::int64_t> before_junctions;
  for (const AtlasJunction& j : before.junctions) before_junctions.insert(j.id);
  for (const AtlasJunction& j : after.junctions) {
    if (before_junctions.count(j.id) == 0) {
      EXPECT_LT(NearestJunction(truth, j.point_m), 0.03)
          << "born junction " << j.id << " is on no junction of the floor";
    }
  }
  // Born: each new marking's line, where it is; nothing that is not on the floor.
  std::set<std::int64_t> before_ids;
  for (const AtlasLine& b : before.lines) before_ids.insert(b.id);
  std::vector<const AtlasLine*> born;
  for (const AtlasLine& l : after.lines) {
    if (before_ids.count(l.id) == 0) born.push_back(&l);
  }
  for (const AtlasLine* l : born) {
    ASSERT_TRUE(l->seen.has_value());
    bool on_floor = false;
    for (const AtlasLine& t : truth.lines) on_floor = on_floor || SameLine(*l, t, 0.03, 0.01);
    EXPECT_TRUE(on_floor) << "born line " << l->id << " (rho " << l->line_map.rho_m << ", alpha "
                          << l->line_map.alpha_rad << ") is on no marking of the floor";
  }
  for (const AtlasLine& t : new_lines) {
    double best_rho = 1e9, best_alpha = 1e9;
    for (const AtlasLine* l : born) {
      if (!ExtentsOverlap(*l, t, 0.0)) continue;
      const Eigen::Vector2d d = perception::LineDifference(l->line_map, t.line_map);
      if (std::abs(d(0)) < best_rho) {
        best_rho = std::abs(d(0));
        best_alpha = std::abs(d(1));
      }
    }
    EXPECT_LT(best_rho, 0.01) << "new line (rho " << t.line_map.rho_m << ") not mapped within 1 cm";
    EXPECT_LT(best_alpha, 0.005);
  }

  // The next drive on the saved atlas. What the first drive left undone is
  // finished (a junction of a vanished tape, in view a few keyframes a pass,
  // gathers its misses over both drives; a landmark seen too briefly may be
  // born now), and only that: everything retired is off the floor, everything
  // born on it.
  const std::filesystem::path path =
      std::filesystem::path(::testing::TempDir()) / "floor_upkeep_atlas.json";
  ASSERT_TRUE(WriteAtlas(path, after).ok());
  const auto loaded = ReadAtlas(path);
  ASSERT_TRUE(loaded.ok()) << loaded.message();
  SlidingWindowSmoother next_on_truth(ShortWindow(SmootherMode::kLocalization), truth);
  const RunErrors again_exact = RunSmoother(changed, testing::TestDriveOptions(10), &next_on_truth);
  SlidingWindowSmoother next(options, *loaded);
  const RunErrors again = RunSmoother(changed, testing::TestDriveOptions(10), &next);
  Print("the next drive on the kept atlas", again);
  std::printf("next drive: %d landmarks born, %d retired\n", next.LandmarksBorn(),
              next.LandmarksRetired());
  EXPECT_LE(next.LandmarksBorn(), 2);
  const Atlas kept = next.CurrentAtlas();
  EXPECT_EQ(
      kept.lines.size() + kept.junctions.size(),
      after.lines.size() + after.junctions.size() + next.LandmarksBorn() - next.LandmarksRetired());
  std::set<std::int64_t> kept_lines_ids, kept_junction_ids;
  for (const AtlasLine& l : kept.lines) kept_lines_ids.insert(l.id);
  for (const AtlasJunction& j : kept.junctions) kept_junction_ids.insert(j.id);
  for (const AtlasLine& l : after.lines) {
    EXPECT_EQ(kept_lines_ids.count(l.id), 1u) << "line " << l.id << " was retired";
  }
  std::set<std::int64_t> after_junctions;
  for (const AtlasJunction& j : after.junctions) {
    after_junctions.insert(j.id);
    if (kept_junction_ids.count(j.id) == 0) {
      EXPECT_GT(NearestJunction(truth, j.point_m), 0.02)
          << "junction " << j.id << " is on the floor but was retired";
    }
  }
  for (const AtlasJunction& j : kept.junctions) {
    if (after_junctions.count(j.id) == 0) {
      EXPECT_LT(NearestJunction(truth, j.point_m), 0.03)
          << "junction " << j.id << " is on no junction of the floor";
    }
  }
  // The kept atlas localizes as well as the floor's true map.
  EXPECT_LT(RunErrors::Rms(again.position_m), RunErrors::Rms(again_exact.position_m) + 0.003);
}

core::FloorMarking Tape(std::int64_t id, Eigen::Vector2d a, Eigen::Vector2d b) {
  core::FloorMarking m;
  m.id = id;
  m.width_m = 0.05;
  m.colour_rgb = {245, 205, 0};
  m.polyline_m = {a, b};
  return m;
}

// A marking in view for a few keyframes a pass (a bar across the drive)
// gathers its misses over drives: the count is kept in the atlas file, and
// the bar taken up is retired on the second drive past it.
TEST(FloorLocalization, AMarkingMissedOnEveryPassIsRetiredOverDrives) {
  core::FloorMap floor;  // two tapes along a 20 m drive
  floor.markings = {Tape(0, {0.0, 0.5}, {20.0, 0.5}), Tape(1, {0.0, -0.5}, {20.0, -0.5})};
  core::FloorMap surveyed = floor;  // and a bar across it, since taken up
  surveyed.markings.push_back(Tape(2, {10.0, -0.4}, {10.0, 0.4}));
  Atlas atlas = AtlasFromFloorMap(surveyed, AtlasFromFloorMapOptions());
  ASSERT_EQ(atlas.lines.size(), 3u);
  const std::int64_t bar = atlas.lines[2].id;
  testing::ZoneDrive drive{floor, {}};
  for (int i = 0; i <= 1000; ++i) {
    drive.trajectory.push_back({0.02 * i, core::SE2(0.02 * i, 0.0, 0.0), std::nullopt});
  }
  SmootherOptions options = ShortWindow(SmootherMode::kLocalization);
  options.upkeep.enabled = true;
  const std::filesystem::path path =
      std::filesystem::path(::testing::TempDir()) / "floor_upkeep_missed.json";
  for (int pass = 1; pass <= 2; ++pass) {
    SlidingWindowSmoother localizer(options, atlas);
    const RunErrors errors = RunSmoother(drive, testing::TestDriveOptions(20 + pass), &localizer);
    // Two tapes along the drive hold it across; along it is the odometry's.
    EXPECT_LT(RunErrors::Rms(errors.position_m), 0.05);
    ASSERT_TRUE(WriteAtlas(path, localizer.CurrentAtlas()).ok());
    const core::Result<Atlas> read = ReadAtlas(path);
    ASSERT_TRUE(read.ok()) << read.message();
    atlas = *read;
    const auto found = std::find_if(atlas.lines.begin(), atlas.lines.end(),
                                    [&](const AtlasLine& l) { return l.id == bar; });
    std::printf("pass %d: %d retired, bar %s\n", pass, localizer.LandmarksRetired(),
                found == atlas.lines.end() ? "retired"
                                           : ("missed " + std::to_string(found->missed)).c_str());
    if (pass == 1) {
      // In view (0.5 m of it 15 cm inside the box) over ~1.3 m of the drive:
      // about 6 keyframes 0.2 m apart, fewer than the 10 that retire it.
      ASSERT_NE(found, atlas.lines.end());
      EXPECT_GE(found->missed, 4);
      EXPECT_LT(found->missed, options.upkeep.retire_after_misses);
      EXPECT_EQ(localizer.LandmarksRetired(), 0);
    } else {
      EXPECT_EQ(found, atlas.lines.end()) << "the bar missed on two passes was kept";
      EXPECT_EQ(localizer.LandmarksRetired(), 1);
    }
    for (const AtlasLine& l : atlas.lines) {
      if (l.id != bar) {
        EXPECT_EQ(l.missed, 0) << "tape " << l.id;
      }
    }
  }
}

}  // namespace
}  // namespace groundline::localization
