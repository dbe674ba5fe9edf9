// Extraction rates on a short simulated sequence: the simulator's floor camera
// (half-resolution reference lens, every nuisance on: texture, wear, scuffs,
// oil, light gradient, glare, blur, noise) over a tape, a stop bar, a
// crosswalk stripe and joints; every visible marking is found, nothing else,
// to the millimetre (one faint far joint aside).
#include <gtest/gtest.h>

#include <numbers>

#include "groundline/perception/ground_truth_lines.h"
#include "groundline/perception/line_evaluation.h"
#include "groundline/perception/line_extractor.h"
#include "groundline/sim/floor_camera.h"
#include "groundline/sim/sim_run.h"

namespace groundline::perception {
namespace {

sim::World TestWorld() {
  sim::World world;
  world.name = "perception_rates";
  world.floor_min_m = core::Vector2(-20, -20);
  world.floor_max_m = core::Vector2(20, 20);
  auto add = [&](core::MarkingKind kind, sim::MarkingColour colour, core::Vector2 a,
                 core::Vector2 b, double width_m) {
    sim::FloorMarking m;
    m.kind = kind;
    m.colour = colour;
    m.polarity = colour == sim::MarkingColour::kGroove ? core::MarkingPolarity::kDark
                                                       : core::MarkingPolarity::kBright;
    m.polyline_m = {a, b};
    m.width_m = width_m;
    world.markings.push_back(m);
  };
  add(core::MarkingKind::kTapeSolid, sim::MarkingColour::kYellow, {-10, 0.4}, {10, 0.4}, 0.075);
  add(core::MarkingKind::kStopBar, sim::MarkingColour::kWhite, {3.7, 0.4}, {3.7, -1.5}, 0.2);
  add(core::MarkingKind::kCrosswalkStripe, sim::MarkingColour::kWhite, {5.0, -0.9}, {6.5, -0.9},
      0.5);
  add(core::MarkingKind::kJoint, sim::MarkingColour::kGroove, {-10, -0.3}, {10, -0.3}, 0.008);
  add(core::MarkingKind::kJoint, sim::MarkingColour::kGroove, {6.0, -10}, {6.0, 10}, 0.008);
  return world;
}

TEST(ExtractionRates, SimulatedSequenceWithNuisances) {
  sim::FloorCameraOptions camera_options;
  camera_options.width_px = 640;
  camera_options.height_px = 512;
  camera_options.focal_px = 566.0;
  const calibration::CameraModel camera = *camera_options.MakeCameraModel();
  const sim::World world = TestWorld();
  sim::FloorRenderOptions render;
  render.seed = 4;
  const sim::FloorRenderer renderer =
      *sim::FloorRenderer::Create(world, camera, camera_options.mount, render);
  const core::FloorMap map = sim::ToFloorMap(world);

  BevRemap::Options remap_options;
  remap_options.supersampling = 2;
  const BevRemap remap(camera, camera_options.mount, remap_options);
  const LineExtractor extractor(remap, LineExtractorOptions{});
  const cv::Mat& mask = extractor.search_mask();
  const FootprintPredicate footprint = [&](const Eigen::Vector2d& p) {
    const Eigen::Vector2d c = remap.grid().CellOfFloorPoint(p);
    const int col = static_cast<int>(std::lround(c.x())),
              row = static_cast<int>(std::lround(c.y()));
    return col >= 0 && row >= 0 && col < mask.cols && row < mask.rows &&
           mask.at<std::uint8_t>(row, col) != 0;
  };
  LineEvaluation evaluation;
  int frame = 0;
  for (const core::SE2& T_map_base : {core::SE2(0.5, 0.1, 0.02), core::SE2(2.2, 0.05, -0.03),
                                      core::SE2(3.9, -0.05, 0.01), core::SE2(4.9, 0.0, 0.0)}) {
    const sim::GreyImage image = renderer.Render(T_map_base, {1.0, 0.0}, frame++);
    const cv::Mat frame_mat(image.height_px, image.width_px, CV_8U,
                            const_cast<std::uint8_t*>(image.pixels.data()));
    cv::Mat bev;
    remap.Apply(frame_mat, &bev);
    const LineExtraction out = extractor.Extract(bev);
    const std::vector<TrueLine> truths = VisibleMarkingLines(map, T_map_base, footprint, {});
    std::vector<LineSegmentEstimate> estimates;
    for (const ExtractedLine& l : out.lines) {
      estimates.push_back({l.line, l.covariance, l.start_m, l.end_m});
    }
    evaluation.AddFrame(out.lines, truths, MatchLines(estimates, truths, {}));
  }
  const LineErrorSummary& s = evaluation.overall();
  EXPECT_GE(s.evaluated_truths, 10);
  // All, with the transverse joint 2.1 m ahead in the third frame, near the
  // far edge of the footprint (8 mm seen at ~4 mm per pixel): it was missed
  // while the BEV was black beyond that edge (BevRemap::Options::fill_unseen).
  EXPECT_EQ(s.detected_truths, s.evaluated_truths);
  EXPECT_EQ(s.false_detections, 0);
  EXPECT_LT(s.MedianAbsRhoErrorM(), 0.003);
  EXPECT_LT(s.MedianAbsAlphaErrorRad(), 0.2 * std::numbers::pi / 180);
  for (const char* kind : {"tape_solid", "stop_bar"}) {
    const LineErrorSummary& k = evaluation.by_truth_kind().at(kind);
    EXPECT_EQ(k.detected_truths, k.evaluated_truths) << kind;
  }
}

// Every nuisance on, no markings: tire scuffs (curved streaks of any
// orientation), oil, texture, glare give no line.
TEST(ExtractionRates, NuisancesAloneGiveNoLines) {
  sim::FloorCameraOptions camera_options;
  camera_options.width_px = 640;
  camera_options.height_px = 512;
  camera_options.focal_px = 566.0;
  const calibration::CameraModel camera = *camera_options.MakeCameraModel();
  sim::World world;
  world.name = "bare_floor";
  world.floor_min_m = core::Vector2(-40, -40);
  world.floor_max_m = core::Vector2(40, 40);
  sim::FloorRenderOptions render;
  render.seed = 8;
  const sim::FloorRenderer renderer =
      *sim::FloorRenderer::Create(world, camera, camera_options.mount, render);
  BevRemap::Options remap_options;
  remap_options.supersampling = 2;
  const BevRemap remap(camera, camera_options.mount, remap_options);
  const LineExtractor extractor(remap, LineExtractorOptions{});
  int frame = 0;
  for (int i = 0; i < 8; ++i) {
    const core::SE2 T_map_base(-30.0 + 7.7 * i, 2.7 * (i % 5) - 6.0, 0.8 * i);
    const sim::GreyImage image = renderer.Render(T_map_base, {1.0, 0.0}, frame++);
    const cv::Mat frame_mat(image.height_px, image.width_px, CV_8U,
                            const_cast<std::uint8_t*>(image.pixels.data()));
    cv::Mat bev;
    remap.Apply(frame_mat, &bev);
    for (const ExtractedLine& l : extractor.Extract(bev).lines) {
      ADD_FAILURE() << "frame " << i << ": a line on a bare floor: " << LineKindName(l.kind)
                    << " rho " << l.line.rho_m << " alpha " << l.line.alpha_rad << " length "
                    << l.LengthM();
    }
  }
}

}  // namespace
}  // namespace groundline::perception
