// Private helpers shared by the zone presets: adding walls, boxes, markings,
// road-graph nodes and moving obstacles to a World under construction.
#ifndef GROUNDLINE_SIM_SRC_ZONE_BUILDER_H_
#define GROUNDLINE_SIM_SRC_ZONE_BUILDER_H_

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "groundline/sim/world.h"
#include "options_check.h"

namespace groundline::sim::internal {

// Width of painted tape (the 5-10 cm lines) and of saw-cut grooves.
inline constexpr double kTapeWidthM = 0.075;
inline constexpr double kJointWidthM = 0.008;
inline constexpr double kBuildingHeightM = 10.0;

class ZoneBuilder {
 public:
  explicit ZoneBuilder(std::string name) { world_.name = std::move(name); }

  // Obstacles. Reflectivity comes from the kind.
  void AddBox(ObstacleKind kind, const OrientedBox& box, double z_min_m, double z_max_m);
  void AddAxisBox(ObstacleKind kind, const Vector2& min_m, const Vector2& max_m,
                  double z_min_m = 0.0, double z_max_m = kBuildingHeightM);
  // A full-height wall of the given thickness centred on a-b.
  void AddWall(const Vector2& a_m, const Vector2& b_m, double thickness_m = 0.3);
  // A pallet stack of footprint_m (x along yaw) and height_m on the floor.
  void AddPalletStack(const Vector2& center_m, const Vector2& footprint_m, double yaw_rad,
                      double height_m);

  // Markings.
  void AddLine(MarkingKind kind, MarkingColour colour, const Vector2& a_m, const Vector2& b_m,
               double width_m, double wear_fraction = 0.0);
  void AddDashedLine(MarkingColour colour, const Vector2& a_m, const Vector2& b_m, double width_m,
                     double dash_m, double gap_m, double wear_fraction = 0.0);
  // A closed rectangular outline (tape centred on the rectangle's boundary).
  void AddStagingBox(const Vector2& min_m, const Vector2& max_m, MarkingColour colour,
                     double width_m, double wear_fraction = 0.0);
  // A zebra crossing across a lane: `num_stripes` stripes parallel to the lane
  // direction (unit `lane_dir`), each stripe_length_m long and stripe_width_m
  // wide, spaced by `pitch_m` across the lane, centred on center_m.
  void AddCrosswalk(const Vector2& center_m, const Vector2& lane_dir, int num_stripes,
                    double stripe_length_m, double stripe_width_m, double pitch_m);
  void AddJoint(const Vector2& a_m, const Vector2& b_m);

  // Road graph.
  int AddNode(const Vector2& p_m);
  void AddEdge(int from, int to, double preference = 1.0);

  // Moving clutter on the road graph: each obstacle follows a random walk of a
  // few edges, shifted sideways by lateral_offset_m (to the right of travel).
  void AddMovingObstacles(MovingKind kind, int count, double lateral_offset_m,
                          std::mt19937_64* rng);

  World& world() { return world_; }
  // Sets the floor rectangle (walls included) and returns the world.
  World Finish(const Vector2& floor_min_m, const Vector2& floor_max_m);

 private:
  World world_;
};

// Uniform double in [lo, hi] from rng.
double Uniform(std::mt19937_64* rng, double lo, double hi);

// Ok if lo <= value <= hi, else "<owner>.<field>: expected a value in [lo, hi], got value".
core::Status CheckRange(const char* owner, const char* field, double value, double lo, double hi);
// Returns the first error among the statuses, or ok.
core::Status FirstError(std::initializer_list<core::Status> statuses);

}  // namespace groundline::sim::internal

#endif  // GROUNDLINE_SIM_SRC_ZONE_BUILDER_H_
