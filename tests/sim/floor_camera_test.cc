#include "groundline/sim/floor_camera.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "groundline/sim/zones.h"
#include "flat_world.h"

namespace groundline::sim {
namespace {

using calibration::CameraModel;

using ::groundline::testing::FlatWorld;

FloorMarking WhiteBand(const Vector2& a, const Vector2& b, double width_m) {
  FloorMarking m;
  m.kind = MarkingKind::kStopBar;
  m.colour = MarkingColour::kWhite;
  m.polyline_m = {a, b};
  m.width_m = width_m;
  return m;
}

// Pixel of a map point seen from T_map_base, through the camera model.
Eigen::Vector2d PredictedPixel(const CameraModel& camera, const calibration::CameraMount& mount,
                               const core::SE2& T_map_base, const Vector2& p_map) {
  const Vector2 p_base = T_map_base.Inverse() * p_map;
  const Eigen::Vector3d p_cam =
      calibration::BaseFromCamera(mount).inverse() * Eigen::Vector3d(p_base.x(), p_base.y(), 0.0);
  return *camera.Project(p_cam);
}

struct Fixture {
  FloorCameraOptions camera_options;
  CameraModel camera = *camera_options.MakeCameraModel();
};

TEST(FloorCamera, DefaultCameraIsTheReferenceLens) {
  const FloorCameraOptions options;
  ASSERT_TRUE(options.Validate().ok());
  const CameraModel camera = *options.MakeCameraModel();
  EXPECT_EQ(camera.lens_model(), "LENSMODEL_OPENCV5");
  EXPECT_NEAR(camera.intrinsics()[0], 6.0 / 0.0053, 1.0);
  EXPECT_EQ(camera.width_px(), 1280);
  EXPECT_EQ(camera.height_px(), 1024);
  FloorCameraOptions bad;
  bad.focal_px = -1.0;
  EXPECT_FALSE(bad.Validate().ok());
  FloorRenderOptions render;
  render.supersampling = 0;
  EXPECT_FALSE(render.Validate().ok());
}

// A small bright square at a known map point: its intensity centroid is the
// camera model's projection of the point (perspective bias of a 2 cm square
// at ~1.5 m is below 0.02 px).
TEST(FloorCamera, FloorPointLandsOnItsPredictedPixel) {
  const Fixture f;
  FloorRenderOptions options = FloorRenderOptions::Ideal();
  options.supersampling = 8;
  const core::SE2 T_map_base(3.0, -2.0, 0.7);
  const std::vector<Vector2> points_base = {{1.2, 0.0}, {1.0, 0.45}, {2.0, -0.6}, {1.6, 0.3}};
  World world = FlatWorld();
  for (const Vector2& pb : points_base) {
    const Vector2 p = T_map_base * pb;
    const Vector2 half(0.01, 0.0);
    world.markings.push_back(WhiteBand(p - half, p + half, 0.02));
  }
  const FloorRenderer renderer = *FloorRenderer::Create(world, f.camera, {}, options);
  const GreyImage image = renderer.Render(T_map_base);
  for (const Vector2& pb : points_base) {
    const Vector2 p = T_map_base * pb;
    const Eigen::Vector2d expected = PredictedPixel(f.camera, {}, T_map_base, p);
    // The flat concrete tone, from a corner far from the square.
    const double background = image.at(5, 5);
    double sw = 0, su = 0, sv = 0;
    const int r = 30;
    for (int v = static_cast<int>(expected.y()) - r; v <= static_cast<int>(expected.y()) + r; ++v) {
      for (int u = static_cast<int>(expected.x()) - r; u <= static_cast<int>(expected.x()) + r;
           ++u) {
        const double wgt = image.at(u, v) - background;
        sw += wgt;
        su += wgt * u;
        sv += wgt * v;
      }
    }
    ASSERT_GT(sw, 1000.0);
    EXPECT_NEAR(su / sw, expected.x(), 0.15) << "floor point " << pb.transpose();
    EXPECT_NEAR(sv / sw, expected.y(), 0.15) << "floor point " << pb.transpose();
  }
}

// The row v where the floor point (x, y) of base_link projects: bisection in x.
double UAtRow(const CameraModel& camera, double y_base, double v_row) {
  const core::SE2 I;
  double lo = 0.7, hi = 2.3;  // v decreases with x
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    (PredictedPixel(camera, {}, I, Vector2(mid, y_base)).y() > v_row ? lo : hi) = mid;
  }
  return PredictedPixel(camera, {}, I, Vector2(0.5 * (lo + hi), y_base)).x();
}

// A straight tape line along base x, off-centre so that distortion bends it:
// per row, the line's centroid and its width in pixels follow the projection.
TEST(FloorCamera, StraightTapeFollowsTheDistortedProjectionWithItsWidth) {
  const Fixture f;
  FloorRenderOptions options = FloorRenderOptions::Ideal();
  options.supersampling = 8;
  World world = FlatWorld();
  const double y = 0.25, width = 0.075;
  world.markings.push_back(WhiteBand({0.0, y}, {4.0, y}, width));
  const FloorRenderer renderer = *FloorRenderer::Create(world, f.camera, {}, options);
  const GreyImage image = renderer.Render(core::SE2());
  const double background = image.at(1279, 512);
  double tape = 0;
  for (const int v : {900, 150}) {  // near (~0.8 m ahead) and far (~2 m ahead)
    const double uc = UAtRow(f.camera, y, v);
    double s = 0, su = 0, peak = 0;
    for (int u = std::max(0, static_cast<int>(uc) - 200);
         u <= std::min(1279, static_cast<int>(uc) + 200); ++u) {
      const double wgt = image.at(u, v) - background;
      s += wgt;
      su += wgt * u;
      peak = std::max(peak, wgt);
    }
    tape = std::max(tape, peak);
    const double expected_width =
        UAtRow(f.camera, y - width / 2, v) - UAtRow(f.camera, y + width / 2, v);
    EXPECT_NEAR(su / s,
                0.5 * (UAtRow(f.camera, y - width / 2, v) + UAtRow(f.camera, y + width / 2, v)),
                0.15)
        << "row " << v;
    EXPECT_NEAR(s / peak, expected_width, 0.25) << "row " << v;
    // The pinhole line (no distortion) would be elsewhere: distortion matters.
    const CameraModel pinhole =
        CameraModel::Pinhole(f.camera.intrinsics()[0], f.camera.intrinsics()[1],
                             f.camera.intrinsics()[2], f.camera.intrinsics()[3], 1280, 1024);
    EXPECT_GT(std::abs(UAtRow(pinhole, y, v) - uc), 2.0) << "row " << v;
  }
  EXPECT_GT(tape, 100.0);
}

// A saw-cut joint running under a tape (listed after it, so an index order
// would paint it on top): the tape covers it, as the layout PNG and the
// perception ground truth have it; beyond the tape the joint shows.
TEST(FloorCamera, TapeCoversAJointRunningUnderIt) {
  const Fixture f;
  FloorRenderOptions options = FloorRenderOptions::Ideal();
  World world = FlatWorld();
  const double y = 0.25;
  FloorMarking tape = WhiteBand({1.0, y}, {2.0, y}, 0.1);
  tape.kind = MarkingKind::kTapeSolid;
  world.markings.push_back(tape);
  FloorMarking joint = WhiteBand({0.0, y}, {4.0, y}, 0.008);
  joint.kind = MarkingKind::kJoint;
  joint.polarity = MarkingPolarity::kDark;
  joint.colour = MarkingColour::kGroove;
  world.markings.push_back(joint);
  const FloorRenderer renderer = *FloorRenderer::Create(world, f.camera, {}, options);
  const GreyImage image = renderer.Render(core::SE2());
  const core::SE2 identity;
  auto grey = [&](double x, double y_m) {
    const Eigen::Vector2d px = PredictedPixel(f.camera, {}, identity, {x, y_m});
    return static_cast<double>(
        image.at(static_cast<int>(std::lround(px.x())), static_cast<int>(std::lround(px.y()))));
  };
  const double tape_grey = grey(1.5, y + 0.03);
  for (const double x : {1.2, 1.5, 1.8}) {
    EXPECT_NEAR(grey(x, y), tape_grey, 3.0) << x;  // on the joint, under the tape
  }
  for (const double x : {0.9, 2.1}) {  // the joint beyond the tape, darker than concrete
    const double concrete = grey(x, y + 0.05);
    EXPECT_GT(tape_grey, concrete + 50.0) << x;
    EXPECT_LT(grey(x, y), concrete - 20.0) << x;
  }
}

// Zone B from a vehicle looking along a solid boundary tape: pixels whose floor
// point (unprojected independently, pixel by pixel) lies well inside a solid
// marking are that marking's tone, pixels well away from every marking are
// concrete.
TEST(FloorCamera, MarkingsInTheMapMatchWhatTheRendererDraws) {
  const Fixture f;
  const World world = *BuildZone(Zone::kB, 1);
  const FloorMarking* tape = nullptr;
  for (const FloorMarking& m : world.markings) {
    if (m.kind == MarkingKind::kTapeSolid && m.polyline_m.size() == 2 &&
        PolylineLength(m.polyline_m) > 8.0) {
      tape = &m;
      break;
    }
  }
  ASSERT_NE(tape, nullptr);
  const Vector2 dir = (tape->polyline_m[1] - tape->polyline_m[0]).normalized();
  const Vector2 normal(-dir.y(), dir.x());
  const core::SE2 T_map_base(tape->polyline_m[0] + 2.0 * dir + 0.25 * normal,
                             std::atan2(dir.y(), dir.x()));
  const FloorRenderer renderer =
      *FloorRenderer::Create(world, f.camera, {}, FloorRenderOptions::Ideal());
  const GreyImage image = renderer.Render(T_map_base);
  const Eigen::Isometry3d T_base_cam = calibration::BaseFromCamera({});
  const double concrete = 255.0 * FloorRenderOptions().concrete_reflectance;
  int inside = 0, outside = 0;
  for (int v = 8; v < 1024; v += 16) {
    for (int u = 8; u < 1280; u += 16) {
      const Eigen::Vector3d ray = T_base_cam.linear() * *f.camera.Unproject(Eigen::Vector2d(u, v));
      ASSERT_LT(ray.z(), 0.0);
      const Eigen::Vector3d pb =
          T_base_cam.translation() - T_base_cam.translation().z() / ray.z() * ray;
      const Vector2 p = T_map_base * Vector2(pb.x(), pb.y());
      double nearest = 1e9;
      const FloorMarking* hit = nullptr;
      for (const FloorMarking& m : world.markings) {
        for (std::size_t i = 1; i < m.polyline_m.size(); ++i) {
          const Vector2 a = m.polyline_m[i - 1], b = m.polyline_m[i];
          const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
          const double d = (p - (a + t * (b - a))).norm() - 0.5 * m.width_m;
          if (d < nearest) {
            nearest = d;
            hit = &m;
          }
        }
      }
      if (nearest > 0.02) {
        EXPECT_NEAR(image.at(u, v), concrete, 1.0) << u << "," << v;
        ++outside;
      } else if (nearest < -0.015 && hit->kind != MarkingKind::kTapeDashed) {
        const bool bright = hit->polarity == MarkingPolarity::kBright;
        EXPECT_EQ(image.at(u, v) > concrete + 40, bright) << u << "," << v;
        EXPECT_EQ(image.at(u, v) < concrete - 40, !bright) << u << "," << v;
        ++inside;
      }
    }
  }
  EXPECT_GT(inside, 20);
  EXPECT_GT(outside, 1000);
}

}  // namespace
}  // namespace groundline::sim
