#include "groundline/sim/wall_faces.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "groundline/localization/atlas_walls.h"
#include "groundline/localization/floor_association.h"
#include "groundline/localization/lidar/wall_lines.h"
#include "groundline/sim/lidar.h"
#include "groundline/sim/zones.h"

namespace groundline::sim {
namespace {

ZoneBOptions SmallZoneB() {
  ZoneBOptions o;
  o.seed = 3;
  o.num_aisles = 2;
  o.aisle_length_m = 20.0;
  o.num_pedestrians = 0;
  return o;
}

// The face with this outward normal whose line passes within 1 mm of point.
const WallFace* FindFace(const std::vector<WallFace>& faces, const Vector2& normal,
                         const Vector2& point_m) {
  for (const WallFace& f : faces) {
    if ((f.outward_normal - normal).norm() < 1e-9 && std::abs(normal.dot(point_m - f.a_m)) < 1e-3) {
      return &f;
    }
  }
  return nullptr;
}

TEST(WallFaces, ZoneBRackFacesAlongEveryAisleAndTheEndWalls) {
  const ZoneBOptions o = SmallZoneB();
  const World world = *BuildZoneB(o);
  const std::vector<WallFace> faces = WallFaces(world, WallFaceOptions());
  const double y0 = o.RackStartYM(), y1 = y0 + o.aisle_length_m;
  for (int i = 0; i < o.num_aisles; ++i) {
    const double xc = o.AisleCenterXM(i), h = 0.5 * o.aisle_clear_width_m;
    for (const auto& [x, normal] :
         {std::pair(xc - h, Vector2(1.0, 0.0)), std::pair(xc + h, Vector2(-1.0, 0.0))}) {
      const WallFace* face = FindFace(faces, normal, Vector2(x, y0));
      ASSERT_NE(face, nullptr) << "aisle " << i << " face x = " << x;
      // The rack run from its first upright; the short end bay (no loads:
      // an opening) may be cut off.
      EXPECT_NEAR(std::min(face->a_m.y(), face->b_m.y()), y0, 0.06);
      EXPECT_NEAR(std::max(face->a_m.y(), face->b_m.y()), y1, o.upright_pitch_m);
      // Uprights with the loads set back behind them.
      EXPECT_TRUE(face->rack_face) << "aisle " << i << " face x = " << x;
    }
  }
  // The backs of the rows (facing a 0.2 m flue or the side wall) are hidden.
  const double back_x = o.AisleCenterXM(0) + 0.5 * o.aisle_clear_width_m + o.rack_depth_m;
  EXPECT_EQ(FindFace(faces, Vector2(1.0, 0.0), Vector2(back_x, y0)), nullptr);
  // The row ends along the cross aisle (uprights, their loads 0.3 m in) are
  // no face.
  EXPECT_EQ(FindFace(faces, Vector2(0.0, -1.0), Vector2(o.AisleCenterXM(0), y0)), nullptr);
  // The inner faces of the end walls along the cross aisles.
  const WallFace* end_wall = FindFace(faces, Vector2(0.0, 1.0), Vector2(0.0, 0.0));
  ASSERT_NE(end_wall, nullptr);
  EXPECT_FALSE(end_wall->rack_face);
  for (const WallFace& f : faces) EXPECT_GE((f.b_m - f.a_m).norm(), 3.0);
}

TEST(WallFaces, TheDockWallIsSolidWithItsDoorsBehindIt) {
  // Zone C's dock wall (face at y = depth) runs between the doors, whose
  // closed leaves stand 10 cm behind it: deeper than a rack's loads, so the
  // wall is not merged across them, and no face of the zone is a rack face.
  ZoneCOptions o;
  o.num_forklifts = 0;
  o.num_pedestrians = 0;
  const World world = *BuildZoneC(o);
  const std::vector<WallFace> faces = WallFaces(world, WallFaceOptions());
  int dock_wall = 0;
  for (const WallFace& f : faces) {
    EXPECT_FALSE(f.rack_face) << f.a_m.transpose() << " - " << f.b_m.transpose();
    dock_wall += (f.outward_normal - Vector2(0.0, -1.0)).norm() < 1e-9 &&
                 std::abs(f.a_m.y() - o.depth_m) < 1e-3;
  }
  EXPECT_GE(dock_wall, 1);
}

TEST(WallFaces, ScansOfTheSimulatedAisleGiveItsFaces) {
  const ZoneBOptions o = SmallZoneB();
  const World world = *BuildZoneB(o);
  std::vector<localization::WallSegment> segments;
  for (const WallFace& f : WallFaces(world, WallFaceOptions())) {
    segments.push_back({f.a_m, f.b_m, f.rack_face});
  }
  localization::Atlas atlas;
  ASSERT_TRUE(localization::AppendWallLines(segments, {}, &atlas).ok());
  LidarOptions lidar_options;
  lidar_options.seed = 9;
  const PlanarLidar lidar(world, lidar_options);
  const localization::lidar::WallLineOptions options;
  int matched = 0;
  for (int k = 0; k < 5; ++k) {
    // Driving north along aisle 1, a little off its centre line and turned.
    const core::SE2 T_map_base(o.AisleCenterXM(1) + 0.1 - 0.05 * k, 8.0 + 2.0 * k,
                               0.5 * std::numbers::pi + 0.02 * (k - 2));
    const LaserScan scan = lidar.Scan(T_map_base, 0.0, k);
    std::vector<double> ranges(scan.ranges_m.begin(), scan.ranges_m.end());
    const std::vector<localization::lidar::RangePoint> points = localization::lidar::RangePointsAt(
        ranges, scan.angle_min_rad, scan.angle_increment_rad, 0.0, 0.0, lidar_options.T_base_lidar,
        core::SE2(), [](double) { return core::SE2(); }, options.min_range_m, options.max_range_m);
    const std::vector<localization::LineObservation> walls =
        localization::lidar::WallLineObservations(
            localization::lidar::ExtractWallLines(points, options));
    // The rack faces of the aisle are found, and whatever the association
    // gate accepts at the true pose is the right face within 1 cm, 0.3 deg.
    // (Pallet sides aligned across the rows make transverse "lines" through
    // the racks; no wall of the atlas is there, the gate rejects them.)
    const core::Matrix3 pose_covariance = core::Vector3(1e-4, 1e-4, 1e-5).asDiagonal();
    int faces = 0;
    for (const localization::Match& m :
         localization::AssociateLines(walls, atlas, T_map_base, pose_covariance, {})) {
      if (m.landmark < 0) continue;
      const localization::LineObservation& z = walls[m.observation];
      const Eigen::Vector2d d = perception::LineDifference(
          perception::InverseTransformLine(T_map_base, atlas.lines[m.landmark].line_map),
          z.line_base);
      EXPECT_LT(std::abs(d(0)), 0.01) << "scan " << k << " rho " << z.line_base.rho_m;
      EXPECT_LT(std::abs(d(1)), 0.3 * std::numbers::pi / 180.0) << "scan " << k;
      faces += std::abs(std::abs(z.line_base.rho_m) - 1.125) < 0.2;
    }
    EXPECT_GE(faces, 1) << "scan " << k;
    EXPECT_LE(faces, 2) << "scan " << k;
    matched += faces;
  }
  // Both faces in (nearly) every scan: the extraction drops a rack band whose
  // front runs off the band's direction (wall_lines.h, step 4c), here one.
  EXPECT_GE(matched, 9);
}

}  // namespace
}  // namespace groundline::sim
