#include "groundline/sim/zones.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

namespace groundline::sim {
namespace {

std::vector<const Obstacle*> OfKind(const World& world, ObstacleKind kind) {
  std::vector<const Obstacle*> out;
  for (const Obstacle& o : world.obstacles) {
    if (o.kind == kind) out.push_back(&o);
  }
  return out;
}

// Free intervals along the line y = const between the side walls, sampled
// every step_m against all obstacles (any height).
std::vector<double> FreeIntervalWidths(const World& world, double y, double step_m) {
  std::vector<const Obstacle*> near_line;
  for (const Obstacle& o : world.obstacles) {
    if (std::abs(o.box.center_m.y() - y) <= o.box.BoundingRadius()) near_line.push_back(&o);
  }
  std::vector<double> widths;
  double start = -1.0;
  for (double x = world.floor_min_m.x(); x <= world.floor_max_m.x(); x += step_m) {
    bool blocked = false;
    for (const Obstacle* o : near_line) blocked = blocked || o->box.Contains({x, y});
    if (!blocked && start < 0.0) start = x;
    if (blocked && start >= 0.0) {
      widths.push_back(x - start);
      start = -1.0;
    }
  }
  return widths;
}

TEST(ZoneB, HasTheRequestedAislesWithExactClearWidthAndLength) {
  const ZoneBOptions o;
  const core::Result<World> world = BuildZoneB(o);
  ASSERT_TRUE(world.ok()) << world.message();

  // Walk across the zone in the middle of a bay: aisles are the wide free gaps.
  const double y = o.RackStartYM() + 10.0 * o.upright_pitch_m + 1.0;
  int aisles = 0;
  for (double w : FreeIntervalWidths(*world, y, 0.005)) {
    if (w < 1.0) continue;
    ++aisles;
    EXPECT_NEAR(w, o.aisle_clear_width_m, 0.006);
  }
  EXPECT_EQ(aisles, 32);

  // Exactly, from the uprights: the faces facing each aisle and the rack run.
  const std::vector<const Obstacle*> uprights = OfKind(*world, ObstacleKind::kRackUpright);
  for (int i = 0; i < o.num_aisles; ++i) {
    const double xc = o.AisleCenterXM(i);
    double left = -1e9, right = 1e9, y_lo = 1e9, y_hi = -1e9;
    std::set<double> ys;
    for (const Obstacle* u : uprights) {
      const double x0 = u->box.center_m.x() - u->box.half_extent_m.x();
      const double x1 = u->box.center_m.x() + u->box.half_extent_m.x();
      if (std::abs(u->box.center_m.x() - xc) > 2.0) continue;
      if (x1 <= xc) left = std::max(left, x1);
      if (x0 >= xc) right = std::min(right, x0);
      y_lo = std::min(y_lo, u->box.center_m.y() - u->box.half_extent_m.y());
      y_hi = std::max(y_hi, u->box.center_m.y() + u->box.half_extent_m.y());
      if (x1 <= xc && x1 > xc - 1.2) ys.insert(u->box.center_m.y());
    }
    EXPECT_NEAR(right - left, o.aisle_clear_width_m, 1e-9) << i;
    EXPECT_NEAR(y_hi - y_lo, o.aisle_length_m, 1e-9) << i;
    // A regular pitch, except for the end frame.
    const std::vector<double> sorted(ys.begin(), ys.end());
    for (std::size_t k = 1; k + 1 < sorted.size(); ++k) {
      EXPECT_NEAR(sorted[k] - sorted[k - 1], o.upright_pitch_m, 1e-9);
    }
  }
  // Beams are above the 0.18 m LiDAR plane, uprights and pallets cross it.
  for (const Obstacle* b : OfKind(*world, ObstacleKind::kRackBeam))
    EXPECT_FALSE(b->IntersectsPlane(0.18));
  for (const Obstacle* p : OfKind(*world, ObstacleKind::kPallet))
    EXPECT_TRUE(p->IntersectsPlane(0.18));
  EXPECT_EQ(OfKind(*world, ObstacleKind::kPallet).size(), 64u * 31u * 2u);

  int stop_bars = 0, tapes = 0;
  for (const FloorMarking& m : world->markings) {
    stop_bars += m.kind == MarkingKind::kStopBar ? 1 : 0;
    const double length_m = std::abs(m.polyline_m[1].y() - m.polyline_m[0].y());
    tapes += m.kind == MarkingKind::kTapeSolid && std::abs(length_m - o.aisle_length_m) < 1e-9;
  }
  EXPECT_EQ(stop_bars, 64);
  EXPECT_EQ(tapes, 64);
}

TEST(ZoneB, OptionsChangeTheGeometry) {
  ZoneBOptions o;
  o.num_aisles = 5;
  o.aisle_length_m = 40.0;
  o.aisle_clear_width_m = 3.0;
  const core::Result<World> world = BuildZoneB(o);
  ASSERT_TRUE(world.ok());
  int aisles = 0;
  for (double w : FreeIntervalWidths(*world, o.RackStartYM() + 20.5, 0.005)) {
    if (w > 1.0) {
      ++aisles;
      EXPECT_NEAR(w, 3.0, 0.006);
    }
  }
  EXPECT_EQ(aisles, 5);
  o.num_aisles = 0;
  const core::Result<World> bad = BuildZoneB(o);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("num_aisles"), std::string::npos) << bad.message();
}

TEST(ZoneD, JointsCrossEveryCorridorEverySixMetres) {
  const ZoneDOptions o;
  const core::Result<World> world = BuildZoneD(o);
  ASSERT_TRUE(world.ok());
  std::vector<double> south_x, cross_y;
  for (const FloorMarking& m : world->markings) {
    if (m.kind != MarkingKind::kJoint) continue;
    EXPECT_EQ(m.polarity, MarkingPolarity::kDark);
    EXPECT_LT(m.width_m, 0.02);
    const Vector2 a = m.polyline_m.front();
    const Vector2 b = m.polyline_m.back();
    if (a.x() == b.x() && a.y() == 0.0) {
      EXPECT_NEAR(b.y(), o.corridor_width_m, 1e-12);  // wall to wall
      south_x.push_back(a.x());
    }
    if (a.y() == b.y() && std::abs(0.5 * (a.x() + b.x()) - o.CrossCorridorCenterXM(1)) < 1e-9) {
      cross_y.push_back(a.y());
    }
  }
  for (std::vector<double>* v : {&south_x, &cross_y}) {
    std::sort(v->begin(), v->end());
    ASSERT_GE(v->size(), 3u);
    for (std::size_t k = 1; k < v->size(); ++k) EXPECT_NEAR((*v)[k] - (*v)[k - 1], 6.0, 1e-9);
  }
  EXPECT_EQ(south_x.size(), 33u);  // 6, 12, ..., 198 in a 200 m corridor
  // Yellow boundary lines run along both sides.
  int yellow = 0;
  for (const FloorMarking& m : world->markings) yellow += m.colour == MarkingColour::kYellow;
  EXPECT_GE(yellow, 8);
}

TEST(ZoneC, HasSixteenDoorsInTheDockWall) {
  const ZoneCOptions o;
  const core::Result<World> world = BuildZoneC(o);
  ASSERT_TRUE(world.ok());
  int wall_pieces = 0;
  for (const Obstacle* w : OfKind(*world, ObstacleKind::kWall)) {
    wall_pieces += std::abs(w->box.center_m.y() - (o.depth_m + 0.15)) < 1e-9 ? 1 : 0;
  }
  EXPECT_EQ(wall_pieces, 17);
  const std::size_t closed = OfKind(*world, ObstacleKind::kDockDoor).size();
  const std::size_t trailers = OfKind(*world, ObstacleKind::kTrailer).size() / 3;
  EXPECT_LE(closed + trailers, 16u);
  EXPECT_GT(closed, 0u);
  EXPECT_GT(trailers, 0u);
  const double area = (o.WidthM()) * o.depth_m;
  EXPECT_NEAR(area, 4500.0, 300.0);
}

TEST(ZoneA, PalletStacksMoveWithTheSeedButTheLayoutDoesNot) {
  ZoneAOptions o;
  const World a1 = *BuildZoneA(o);
  const World a1_again = *BuildZoneA(o);
  o.seed = 2;
  const World a2 = *BuildZoneA(o);
  auto pallets = [](const World& w) {
    std::vector<std::pair<double, double>> out;
    for (const Obstacle* p : OfKind(w, ObstacleKind::kPallet)) {
      out.emplace_back(p->box.center_m.x(), p->box.center_m.y());
    }
    return out;
  };
  EXPECT_EQ(pallets(a1), pallets(a1_again));
  EXPECT_NE(pallets(a1), pallets(a2));
  EXPECT_GT(pallets(a1).size(), 100u);
  EXPECT_EQ(OfKind(a1, ObstacleKind::kColumn).size(), OfKind(a2, ObstacleKind::kColumn).size());
  ASSERT_EQ(a1.markings.size(), a2.markings.size());
  for (std::size_t i = 0; i < a1.markings.size(); ++i) {
    EXPECT_EQ(a1.markings[i].polyline_m, a2.markings[i].polyline_m);
  }
  EXPECT_NE(a1.moving.front().path_m, a2.moving.front().path_m);
  EXPECT_NEAR(o.width_m * o.depth_m, 6500.0, 1.0);
}

TEST(Zones, MarkingsAreWellFormedInEveryZone) {
  for (Zone zone : {Zone::kA, Zone::kB, Zone::kC, Zone::kD}) {
    const core::Result<World> world = BuildZone(zone, 5);
    ASSERT_TRUE(world.ok()) << world.message();
    std::set<MarkingKind> kinds;
    for (const FloorMarking& m : world->markings) {
      kinds.insert(m.kind);
      ASSERT_GE(m.polyline_m.size(), 2u);
      EXPECT_GT(m.width_m, 0.0);
      EXPECT_GT(PolylineLength(m.polyline_m), 0.0);
      if (m.kind == MarkingKind::kTapeDashed) {
        EXPECT_GT(m.dash_length_m, 0.0);
        EXPECT_GT(m.gap_length_m, 0.0);
      }
      if (m.kind == MarkingKind::kStagingBoxEdge) {
        EXPECT_EQ(m.polyline_m.front(), m.polyline_m.back());
      }
      if (m.kind != MarkingKind::kJoint) {
        EXPECT_GE(m.width_m, 0.05);
        EXPECT_EQ(m.polarity, MarkingPolarity::kBright);
      }
    }
    EXPECT_TRUE(kinds.count(MarkingKind::kJoint));
    EXPECT_TRUE(kinds.count(MarkingKind::kTapeSolid));
    if (zone == Zone::kA) {
      EXPECT_TRUE(kinds.count(MarkingKind::kCrosswalkStripe));
      EXPECT_TRUE(kinds.count(MarkingKind::kStagingBoxEdge));
      EXPECT_TRUE(kinds.count(MarkingKind::kTapeDashed));
    }
    EXPECT_FALSE(world->roads.edges.empty());
    for (const MovingObstacle& m : world->moving) EXPECT_GT(PolylineLength(m.path_m), 0.0);
  }
}

TEST(Zones, ParseZoneAcceptsTheFourLetters) {
  EXPECT_EQ(*ParseZone("b"), Zone::kB);
  EXPECT_EQ(*ParseZone("D"), Zone::kD);
  const core::Result<Zone> bad = ParseZone("E");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("A, B, C, D"), std::string::npos);
}

}  // namespace
}  // namespace groundline::sim
