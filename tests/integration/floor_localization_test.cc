// Floor-line localization end to end on simulated zone drives (observations
// generated from the floor map at the true poses, with their stated noise;
// not the extractor): localization on a surveyed atlas against the
// odometry-only baseline, NEES consistency, and mapping an atlas, saving it,
// then localizing on the saved file.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "floor_localization_run.h"
#include "groundline/localization/atlas.h"

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

}  // namespace
}  // namespace groundline::localization
