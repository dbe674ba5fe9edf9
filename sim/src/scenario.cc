// Scenario files (scenario.h): YAML to SimRunOptions through tables of keys.
#include "groundline/sim/scenario.h"

#include <cstdint>
#include <numbers>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "groundline/core/yaml_fields.h"

namespace groundline::sim {
namespace {

using core::internal::JoinPath;
using core::internal::YamlFields;

constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr double kMmToM = 1e-3;

// One optional key of a mapping and where its value goes (times `scale`).
struct Field {
  const char* key;
  std::variant<double*, int*, bool*, std::uint64_t*> target;
  double scale = 1.0;
};

// Reads the keys of `fields` present in `map` (at `path`); keys not in the
// table, nor in `sections` (handled by the caller), are errors.
void ReadFields(YamlFields& y, const YAML::Node& map, std::string_view path,
                const std::vector<Field>& fields,
                const std::vector<std::string_view>& sections = {}) {
  if (!map || !y.ExpectMap(map, path)) return;
  std::vector<std::string_view> allowed = sections;
  for (const Field& f : fields) allowed.push_back(f.key);
  y.CheckKeys(map, path, allowed);
  for (const Field& f : fields) {
    const YAML::Node node = map[f.key];
    if (!node) continue;
    const std::string at = JoinPath(path, f.key);
    if (double* const* d = std::get_if<double*>(&f.target)) {
      **d = y.NumberAt(node, at) * f.scale;
    } else if (int* const* i = std::get_if<int*>(&f.target)) {
      **i = static_cast<int>(y.IntegerAt(node, at));
    } else if (bool* const* b = std::get_if<bool*>(&f.target)) {
      **b = y.BoolAt(node, at);
    } else if (std::uint64_t* const* u = std::get_if<std::uint64_t*>(&f.target)) {
      const std::int64_t v = y.IntegerAt(node, at);
      if (v < 0) y.Fail(node, at, "an integer >= 0", node.Scalar());
      **u = static_cast<std::uint64_t>(v);
    }
  }
}

std::vector<Field> LayoutFields(Zone zone, SimRunOptions* o) {
  switch (zone) {
    case Zone::kA: {
      ZoneAOptions& z = o->zone_a;
      return {{"width_m", &z.width_m},
              {"depth_m", &z.depth_m},
              {"num_lanes_x", &z.num_lanes_x},
              {"num_lanes_y", &z.num_lanes_y},
              {"lane_width_m", &z.lane_width_m},
              {"wall_to_lane_center_m", &z.wall_to_lane_center_m},
              {"staging_box_width_m", &z.staging_box_width_m},
              {"staging_box_depth_m", &z.staging_box_depth_m},
              {"staging_box_gap_m", &z.staging_box_gap_m},
              {"access_gap_m", &z.access_gap_m},
              {"box_to_lane_m", &z.box_to_lane_m},
              {"pallet_occupancy", &z.pallet_occupancy},
              {"joint_spacing_m", &z.joint_spacing_m},
              {"num_forklifts", &z.num_forklifts},
              {"num_pedestrians", &z.num_pedestrians}};
    }
    case Zone::kB: {
      ZoneBOptions& z = o->zone_b;
      return {{"num_aisles", &z.num_aisles},
              {"aisle_length_m", &z.aisle_length_m},
              {"aisle_clear_width_m", &z.aisle_clear_width_m},
              {"upright_pitch_m", &z.upright_pitch_m},
              {"upright_width_m", &z.upright_width_m},
              {"upright_depth_m", &z.upright_depth_m},
              {"rack_depth_m", &z.rack_depth_m},
              {"flue_gap_m", &z.flue_gap_m},
              {"wall_gap_m", &z.wall_gap_m},
              {"cross_aisle_width_m", &z.cross_aisle_width_m},
              {"first_beam_height_m", &z.first_beam_height_m},
              {"rack_height_m", &z.rack_height_m},
              {"pallets_per_bay", &z.pallets_per_bay},
              {"pallet_width_m", &z.pallet_width_m},
              {"pallet_depth_m", &z.pallet_depth_m},
              {"pallet_height_m", &z.pallet_height_m},
              {"pallet_setback_m", &z.pallet_setback_m},
              {"pallet_fill", &z.pallet_fill},
              {"tape_offset_m", &z.tape_offset_m},
              {"stop_bar_width_m", &z.stop_bar_width_m},
              {"stop_bar_inset_m", &z.stop_bar_inset_m},
              {"joint_spacing_m", &z.joint_spacing_m},
              {"num_pedestrians", &z.num_pedestrians}};
    }
    case Zone::kC: {
      ZoneCOptions& z = o->zone_c;
      return {{"num_doors", &z.num_doors},
              {"doors_per_group", &z.doors_per_group},
              {"door_width_m", &z.door_width_m},
              {"door_pitch_m", &z.door_pitch_m},
              {"group_gap_m", &z.group_gap_m},
              {"end_margin_m", &z.end_margin_m},
              {"depth_m", &z.depth_m},
              {"lane_width_m", &z.lane_width_m},
              {"main_lane_center_y_m", &z.main_lane_center_y_m},
              {"apron_lane_from_wall_m", &z.apron_lane_from_wall_m},
              {"staging_lane_width_m", &z.staging_lane_width_m},
              {"staging_lane_length_m", &z.staging_lane_length_m},
              {"door_open_probability", &z.door_open_probability},
              {"trailer_probability", &z.trailer_probability},
              {"pallet_occupancy", &z.pallet_occupancy},
              {"tape_wear_fraction", &z.tape_wear_fraction},
              {"joint_spacing_m", &z.joint_spacing_m},
              {"num_forklifts", &z.num_forklifts},
              {"num_pedestrians", &z.num_pedestrians}};
    }
    case Zone::kD: {
      ZoneDOptions& z = o->zone_d;
      return {{"corridor_length_m", &z.corridor_length_m},
              {"corridor_width_m", &z.corridor_width_m},
              {"corridor_separation_m", &z.corridor_separation_m},
              {"num_cross_corridors", &z.num_cross_corridors},
              {"joint_spacing_m", &z.joint_spacing_m},
              {"boundary_line_offset_m", &z.boundary_line_offset_m},
              {"boundary_line_width_m", &z.boundary_line_width_m},
              {"num_forklifts", &z.num_forklifts},
              {"num_pedestrians", &z.num_pedestrians}};
    }
  }
  return {};
}

void ReadNuisances(YamlFields& y, const YAML::Node& map, FloorRenderOptions* r, bool* randomized) {
  if (!map || !y.ExpectMap(map, "nuisances")) return;
  const std::vector<std::pair<const char*, std::vector<Field>>> sections = {
      {"randomized", {{"enabled", randomized}}},
      {"texture", {{"enabled", &r->texture}, {"contrast", &r->texture_contrast}}},
      {"wear", {{"enabled", &r->wear}}},
      {"scuffs", {{"enabled", &r->scuffs}, {"darkness", &r->scuff_darkness}}},
      {"oil", {{"enabled", &r->oil}, {"darkness", &r->oil_darkness}}},
      {"illumination",
       {{"lux", &r->lux},
        {"exposure_reference_lux", &r->exposure_reference_lux},
        {"gradient", &r->illumination_gradient},
        {"gradient_fraction", &r->gradient_fraction}}},
      {"shadows",
       {{"enabled", &r->shadows}, {"factor", &r->shadow_factor}, {"cover", &r->shadow_cover}}},
      {"glare",
       {{"enabled", &r->glare},
        {"peak_dn", &r->glare_peak_dn},
        {"sigma_m", &r->glare_sigma_m},
        {"luminaire_spacing_x_m", &r->luminaire_spacing_x_m},
        {"luminaire_spacing_y_m", &r->luminaire_spacing_y_m},
        {"row_pitch_m", &r->glare_row_pitch_m},
        {"row_length_m", &r->glare_row_length_m}}},
      {"cast_shadows",
       {{"enabled", &r->cast_shadows},
        {"factor", &r->cast_shadow_factor},
        {"cover", &r->cast_shadow_cover},
        {"penumbra_m", &r->shadow_penumbra_m}}},
      {"vehicle_shadow",
       {{"enabled", &r->vehicle_shadow},
        {"factor", &r->vehicle_shadow_factor},
        {"luminaire_height_m", &r->luminaire_height_m},
        {"vehicle_height_m", &r->vehicle_height_m}}},
      {"tire_marks",
       {{"enabled", &r->tire_marks},
        {"darkness", &r->tire_mark_darkness},
        {"density_per_100m2", &r->tire_mark_density}}},
      {"patches",
       {{"enabled", &r->patches}, {"contrast", &r->patch_contrast}, {"cover", &r->patch_cover}}},
      {"wet",
       {{"enabled", &r->wet},
        {"darkness", &r->wet_darkness},
        {"cover", &r->wet_cover},
        {"glare_gain", &r->wet_glare_gain}}},
      {"motion_blur", {{"enabled", &r->motion_blur}, {"exposure_s", &r->exposure_s}}},
      {"occlusion", {{"enabled", &r->occlusion}}},
      {"standing_objects",
       {{"enabled", &r->standing_objects}, {"clutter_per_100m", &r->clutter_per_100m}}},
      {"noise",
       {{"enabled", &r->noise},
        {"read_noise_dn", &r->read_noise_dn},
        {"electrons_per_dn", &r->electrons_per_dn}}},
  };
  std::vector<std::string_view> names;
  for (const auto& [name, fields] : sections) names.push_back(name);
  y.CheckKeys(map, "nuisances", names);
  for (const auto& [name, fields] : sections) {
    ReadFields(y, map[name], JoinPath("nuisances", name), fields);
  }
}

void ReadPerturbations(YamlFields& y, const YAML::Node& map, MountPerturbationOptions* p) {
  if (!map) return;
  ReadFields(y, map, "perturbations",
             {{"height_loss_mm_per_km", &p->height_loss_m_per_km, kMmToM},
              {"drift_step_mm", &p->drift_step_m, kMmToM}},
             {"steps"});
  const YAML::Node steps = map["steps"];
  if (!steps || !y.ok() || !y.ExpectSequence(steps, "perturbations.steps")) return;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const std::string path = core::internal::IndexPath("perturbations.steps", i);
    MountStep step;
    ReadFields(y, steps[i], path,
               {{"at_s", &step.at_s},
                {"height_mm", &step.height_m, kMmToM},
                {"pitch_deg", &step.pitch_rad, kDegToRad},
                {"roll_deg", &step.roll_rad, kDegToRad},
                {"yaw_deg", &step.yaw_rad, kDegToRad},
                {"forward_mm", &step.forward_m, kMmToM},
                {"lateral_mm", &step.lateral_m, kMmToM}},
               {"cause"});
    if (!y.ok()) return;
    if (!steps[i]["at_s"]) y.Fail(steps[i], JoinPath(path, "at_s"), "a time", "nothing");
    if (steps[i]["cause"]) {
      step.cause = y.Text(steps[i], path, "cause");
      if (step.cause != "payload" && step.cause != "knock" && step.cause != "height") {
        y.Fail(steps[i]["cause"], JoinPath(path, "cause"), "payload, knock or height", step.cause);
      }
    }
    p->steps.push_back(step);
  }
}

}  // namespace

namespace {

core::Result<Scenario> LoadScenarioUnguarded(const std::filesystem::path& path) {
  core::Result<YAML::Node> loaded = core::internal::LoadYamlFile(path);
  if (!loaded.ok()) return loaded.status();
  const YAML::Node& root = *loaded;
  YamlFields y(path.string());
  int major = 0, minor = 0;
  y.CheckFormat(root, kScenarioFormatName, kScenarioFormatMajor, kScenarioFormatMinor, &major,
                &minor);
  if (!y.ok()) return y.status();
  Scenario scenario;
  SimRunOptions& o = scenario.options;
  if (root["zone"]) {
    const std::string zone = y.Text(root, "", "zone");
    if (y.ok()) {
      core::Result<Zone> parsed = ParseZone(zone);
      if (!parsed.ok()) y.Fail(root["zone"], "zone", "A, B, C or D", zone);
      if (parsed.ok()) o.zone = *parsed;
    }
  }
  ReadFields(y, root, "", {{"seed", &o.seed}, {"robots", &scenario.robots}},
             {"format", "version", "name", "description", "zone", "layout", "route", "encoders",
              "lidar", "camera", "nuisances", "perturbations", "survey_noise"});
  if (root["robots"] && y.ok() && scenario.robots < 1) {
    y.Fail(root["robots"], "robots", "a number of robots >= 1", root["robots"].Scalar());
  }
  if (!y.ok()) return y.status();
  ReadFields(y, root["layout"], "layout", LayoutFields(o.zone, &o));
  RouteOptions& r = o.route;
  ReadFields(y, root["route"], "route",
             {{"length_m", &r.length_m},
              {"closed_loop", &r.closed_loop},
              {"length_tolerance_fraction", &r.length_tolerance_fraction},
              {"max_walk_attempts", &r.max_walk_attempts},
              {"min_speed_mps", &r.min_speed_mps},
              {"max_speed_mps", &r.max_speed_mps},
              {"max_lateral_accel_mps2", &r.max_lateral_accel_mps2},
              {"max_accel_mps2", &r.max_accel_mps2},
              {"turn_radius_m", &r.turn_radius_m},
              {"min_turn_radius_m", &r.min_turn_radius_m},
              {"transition_length_m", &r.transition_length_m},
              {"max_turn_angle_deg", &r.max_turn_angle_rad, kDegToRad},
              {"min_clearance_m", &r.min_clearance_m},
              {"sample_rate_hz", &r.sample_rate_hz},
              {"tracking_deviation_m", &r.tracking_deviation_m},
              {"tracking_wavelength_min_m", &r.tracking_wavelength_min_m},
              {"tracking_wavelength_max_m", &r.tracking_wavelength_max_m}});
  WheelEncoderOptions& e = o.encoders;
  ReadFields(y, root["encoders"], "encoders",
             {{"ticks_per_revolution", &e.ticks_per_revolution},
              {"radius_scale_stddev", &e.radius_scale_stddev},
              {"left_radius_scale", &e.left_radius_scale},
              {"right_radius_scale", &e.right_radius_scale},
              {"track_scale", &e.track_scale},
              {"wheel_variance_m2_per_m", &e.wheel_variance_m2_per_m},
              {"slip_rate_per_m", &e.slip_rate_per_m},
              {"slip_mean_m", &e.slip_mean_m},
              {"wheel_radius_m", &o.drive.wheel_radius_m},
              {"track_m", &o.drive.track_m}});
  LidarOptions& l = o.lidar;
  ReadFields(y, root["lidar"], "lidar",
             {{"enabled", &o.with_lidar},
              {"rate_hz", &l.rate_hz},
              {"height_m", &l.height_m},
              {"field_of_view_deg", &l.field_of_view_rad, kDegToRad},
              {"angular_resolution_deg", &l.angular_resolution_rad, kDegToRad},
              {"range_min_m", &l.range_min_m},
              {"range_max_m", &l.range_max_m},
              {"range_noise_sigma_m", &l.range_noise_sigma_m},
              {"dropout_probability", &l.dropout_probability}});
  FloorCameraOptions& c = o.camera;
  calibration::CameraMount& m = c.mount;
  ReadFields(y, root["camera"], "camera",
             {{"enabled", &o.with_camera},
              {"rate_hz", &o.camera_rate_hz},
              {"width_px", &c.width_px},
              {"height_px", &c.height_px},
              {"focal_px", &c.focal_px},
              {"supersampling", &o.render.supersampling}},
             {"mount"});
  if (root["camera"] && y.ok()) {
    ReadFields(y, root["camera"]["mount"], "camera.mount",
               {{"height_m", &m.height_m},
                {"pitch_deg", &m.pitch_rad, kDegToRad},
                {"roll_deg", &m.roll_rad, kDegToRad},
                {"yaw_deg", &m.yaw_rad, kDegToRad},
                {"forward_m", &m.forward_m},
                {"lateral_m", &m.lateral_m}});
  }
  ReadNuisances(y, root["nuisances"], &o.render, &o.randomize_nuisances);
  ReadPerturbations(y, root["perturbations"], &o.mount_perturbations);
  ReadFields(y, root["survey_noise"], "survey_noise",
             {{"marking_vertex_sigma_m", &o.survey_noise.marking_vertex_sigma_m},
              {"face_offset_sigma_m", &o.survey_noise.face_offset_sigma_m},
              {"face_angle_deg", &o.survey_noise.face_angle_sigma_rad, kDegToRad}});
  if (!y.ok()) return y.status();
  if (core::Status s = o.Validate(); !s.ok()) return s.WithContext(path.string());
  return scenario;
}

}  // namespace

// A yaml-cpp exception escaping the walk becomes an error (no reader throws).
core::Result<Scenario> LoadScenario(const std::filesystem::path& path) {
  return core::internal::CatchYamlErrors(path.string(),
                                         [&] { return LoadScenarioUnguarded(path); });
}

}  // namespace groundline::sim
