// The floor's texture tracked between two rendered frames (the simulator's
// floor camera, every nuisance on): under the true mount the tracked patches
// are where the vehicle's motion puts them; under a wrong pitch they are not,
// by millimetres the mount's self-calibration reads.
#include "groundline/perception/floor_texture_flow.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
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

// The simulator's floor camera over a bare concrete floor (render seed 11).
class BareFloorCamera {
 public:
  BareFloorCamera() : camera_(*sim::FloorCameraOptions().MakeCameraModel()) {
    world_.name = "bare_floor";
    world_.floor_min_m = core::Vector2(-5, -5);
    world_.floor_max_m = core::Vector2(5, 5);
    sim::FloorRenderOptions render;
    render.seed = 11;
    renderer_.emplace(*sim::FloorRenderer::Create(world_, camera_, mount(), render));
  }
  const calibration::CameraModel& camera() const { return camera_; }
  calibration::CameraMount mount() const { return sim::FloorCameraOptions().mount; }
  // The grey frame at pose T (frame_index seeds its noise).
  cv::Mat Frame(const core::SE2& T, int frame_index) const {
    const sim::GreyImage image = renderer_->Render(T, {1.35, 0.0}, frame_index);
    return cv::Mat(image.height_px, image.width_px, CV_8U,
                   const_cast<std::uint8_t*>(image.pixels.data()))
        .clone();
  }

 private:
  calibration::CameraModel camera_;
  sim::World world_;
  std::optional<sim::FloorRenderer> renderer_;
};

RenderedPair Render() {
  const BareFloorCamera floor;
  return {floor.camera(), floor.mount(), floor.Frame(kFirst, 0), floor.Frame(kSecond, 1)};
}

// Per tracked patch: how far apart its two floor points lie once moved into
// the map by the frames' true poses (0 for a patch of floor under the right
// mount), with the points remapped from the BEV's mount to `solve_mount`.
std::vector<double> MeetingErrors(const RenderedPair& pair, const calibration::CameraMount& bev_mount,
                                  const calibration::CameraMount& solve_mount, int* tracked) {
  const BevRemap remap(pair.camera, bev_mount, BevRemap::Options::ForTextureTracking());
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
  ASSERT_GE(tracked, 50);
  ASSERT_EQ(static_cast<int>(e.size()), tracked);
  // About a twentieth of a 4 mm cell (0.15 mm at the median, 0.28 mm at the
  // 90th percentile when written).
  EXPECT_LT(Quantile(e, 0.5), 0.0003);
  EXPECT_LT(Quantile(e, 0.9), 0.0005);
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
  ASSERT_GE(tracked, 50);
  const std::vector<double> fixed = MeetingErrors(pair, wrong, pair.truth, &tracked);
  EXPECT_GT(Quantile(off, 0.5), 0.005);  // 7.4 mm when written
  EXPECT_LT(Quantile(fixed, 0.5), 0.0003);
}

// A vehicle at constant speed moves the floor by the same fraction of a cell
// in every frame pair: a bias of the tracking that depends on that fraction
// and is common to all patches would be read as a scale, i.e. a camera
// height off by up to a millimetre for minutes. Over one cell of sub-cell
// phases (27.0-27.4 cm in 1 mm steps), the patches' mean along-track
// error stays within 0.1 mm at every phase (0.05 mm when written; on the
// line extraction's 1 cm cells it reached 0.74 mm).
TEST(FloorTextureFlow, NoBiasCommonToThePatchesAtAnySubCellPhase) {
  const BareFloorCamera floor;
  const BevRemap remap(floor.camera(), floor.mount(), BevRemap::Options::ForTextureTracking());
  const double cells_per_m = 1.0 / remap.grid().cell_m();
  cv::Mat bev0, bev1;
  remap.Apply(floor.Frame(kFirst, 0), &bev0);
  double worst = 0.0;
  for (int step = 0; step <= 4; ++step) {
    const core::SE2 second(0.27 + 0.001 * step, 0.004, 0.002);
    remap.Apply(floor.Frame(second, 1), &bev1);
    const std::vector<FloorTextureMatch> matches =
        TrackFloorTexture(bev0, remap.valid_mask(), bev1, remap.valid_mask(),
                          cells_per_m * Eigen::Vector2d(0.004, second.x()), {});
    ASSERT_GE(matches.size(), 50u);
    double sum = 0.0;
    for (const FloorTextureMatch& m : matches) {
      const Eigen::Vector2d p0 = kFirst * remap.grid().FloorPointOfCell(m.previous_cell);
      const Eigen::Vector2d p1 = second * remap.grid().FloorPointOfCell(m.current_cell);
      sum += p1.x() - p0.x();
    }
    const double mean = sum / static_cast<double>(matches.size());
    worst = std::max(worst, std::abs(mean));
  }
  EXPECT_LT(worst, 0.0001);
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
