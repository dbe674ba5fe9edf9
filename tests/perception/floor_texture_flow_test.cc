// The floor's texture tracked between two rendered frames (the simulator's
// floor camera, every nuisance on): under the true mount the tracked patches
// are where the vehicle's motion puts them; under a wrong pitch they are not,
// by millimetres the mount's self-calibration reads.
#include "groundline/perception/floor_texture_flow.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "groundline/calibration/mount_remap.h"
#include "groundline/core/angles.h"
#include "groundline/perception/bev_remap.h"
#include "groundline/sim/floor_camera.h"

namespace groundline::perception {
namespace {

struct RenderedPair {
  calibration::CameraModel camera;
  calibration::CameraMount truth;
  cv::Mat first, second;  // grey frames
};

const core::SE2 kFirst(0.0, 0.0, 0.0);
const core::SE2 kSecond(0.27, 0.012, 0.006);  // one frame at 1.35 m/s, 5 Hz

RenderedPair Render() {
  sim::FloorCameraOptions camera_options;
  RenderedPair out{*camera_options.MakeCameraModel(), camera_options.mount, {}, {}};
  sim::World world;
  world.name = "bare_floor";
  world.floor_min_m = core::Vector2(-40, -40);
  world.floor_max_m = core::Vector2(40, 40);
  sim::FloorRenderOptions render;
  render.seed = 11;
  const sim::FloorRenderer renderer =
      *sim::FloorRenderer::Create(world, out.camera, out.truth, render);
  int index = 0;
  for (const core::SE2& T : {kFirst, kSecond}) {
    const sim::GreyImage image = renderer.Render(T, {1.35, 0.0}, index++);
    cv::Mat grey(image.height_px, image.width_px, CV_8U,
                 const_cast<std::uint8_t*>(image.pixels.data()));
    (index == 1 ? out.first : out.second) = grey.clone();
  }
  return out;
}

// Per tracked patch: how far apart its two floor points lie once moved into
// the map by the frames' true poses (0 for a patch of floor under the right
// mount), with the points remapped from the BEV's mount to `solve_mount`.
std::vector<double> MeetingErrors(const RenderedPair& pair, const calibration::CameraMount& bev_mount,
                                  const calibration::CameraMount& solve_mount, int* tracked) {
  const BevRemap remap(pair.camera, bev_mount, BevRemap::Options::ForLineExtraction());
  cv::Mat bev0, bev1;
  remap.Apply(pair.first, &bev0);
  remap.Apply(pair.second, &bev1);
  const std::vector<FloorTextureMatch> matches = TrackFloorTexture(
      bev0, remap.valid_mask(), bev1, remap.valid_mask(), Eigen::Vector2d::Zero(), {});
  *tracked = static_cast<int>(matches.size());
  std::vector<double> errors;
  for (const FloorTextureMatch& m : matches) {
    Eigen::Vector2d p0, p1;
    if (!calibration::RemapFloorPoint(remap.grid().FloorPointOfCell(m.previous_cell), bev_mount,
                                      solve_mount, &p0) ||
        !calibration::RemapFloorPoint(remap.grid().FloorPointOfCell(m.current_cell), bev_mount,
                                      solve_mount, &p1))
      continue;
    errors.push_back(((kSecond * p1) - (kFirst * p0)).norm());
  }
  std::sort(errors.begin(), errors.end());
  return errors;
}

double Quantile(const std::vector<double>& sorted, double q) {
  return sorted[static_cast<std::size_t>(q * (sorted.size() - 1))];
}

TEST(FloorTextureFlow, RenderedConcreteMovesWithTheVehicle) {
  const RenderedPair pair = Render();
  int tracked = 0;
  const std::vector<double> e = MeetingErrors(pair, pair.truth, pair.truth, &tracked);
  ASSERT_GE(tracked, 20);
  ASSERT_EQ(static_cast<int>(e.size()), tracked);
  // About a tenth of a 1 cm cell (0.9 mm at the median, 1.4 mm the worst
  // when written): the self-calibration's flow_sigma_m (1 mm) is this noise.
  EXPECT_LT(Quantile(e, 0.5), 0.0015);
  EXPECT_LT(Quantile(e, 0.9), 0.0025);
}

// The evidence: a BEV made under a pitch 0.5 deg off puts the patches
// centimetres from where the motion takes them; remapped to the true mount
// they meet again.
TEST(FloorTextureFlow, UnderAWrongPitchThePatchesDoNotMeet) {
  const RenderedPair pair = Render();
  calibration::CameraMount wrong = pair.truth;
  wrong.pitch_rad += 0.5 * core::kDegToRad;
  int tracked = 0;
  const std::vector<double> off = MeetingErrors(pair, wrong, wrong, &tracked);
  ASSERT_GE(tracked, 20);
  const std::vector<double> fixed = MeetingErrors(pair, wrong, pair.truth, &tracked);
  EXPECT_GT(Quantile(off, 0.5), 0.005);  // 8 mm when written
  EXPECT_LT(Quantile(fixed, 0.5), 0.0015);
}

TEST(FloorTextureFlow, ImagesThatDoNotMatchGiveNoPatches) {
  const cv::Mat a(100, 120, CV_8U, cv::Scalar(80)), seen(100, 120, CV_8U, cv::Scalar(255));
  EXPECT_TRUE(TrackFloorTexture(a, seen, cv::Mat(), seen, Eigen::Vector2d::Zero(), {}).empty());
  const cv::Mat b(90, 120, CV_8U, cv::Scalar(80));
  EXPECT_TRUE(TrackFloorTexture(a, seen, b, seen, Eigen::Vector2d::Zero(), {}).empty());
}

TEST(FloorTextureFlowOptions, ErrorsNameTheField) {
  FloorTextureFlowOptions o;
  EXPECT_TRUE(o.Validate().ok());
  o.window_px = 20;
  EXPECT_NE(o.Validate().message().find("window_px"), std::string::npos);
  o = {};
  o.max_forward_backward_px = 0.0;
  EXPECT_NE(o.Validate().message().find("max_forward_backward_px"), std::string::npos);
}

}  // namespace
}  // namespace groundline::perception
