#include "localizer_impl.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <ctime>
#include <string>

#include "groundline/core/covariance.h"
#include "groundline/core/run_timing.h"
#include "groundline/core/trajectory_association.h"

namespace groundline::localization::internal {

core::Result<std::unique_ptr<LocalizerImpl>> LocalizerImpl::Create(const LocalizerOptions& options,
                                                                   LocalizerSetup setup) {
  if (core::Status s = options.Validate(); !s.ok()) return s;
  if (core::Status s = setup.drive.Validate(); !s.ok()) return s.WithContext("localizer drive");
  const bool needs_lidar = options.mode == LocalizerMode::kLidar ||
                           (options.use_lidar && (options.mode == LocalizerMode::kLines ||
                                                  options.mode == LocalizerMode::kMapping));
  if (needs_lidar && !setup.lidar) {
    return core::Status::Error(
        "localizer: the LiDAR is enabled but the setup has no LiDAR (its mounting pose and rate)");
  }
  if (setup.lidar && !(setup.lidar->rate_hz > 0.0)) {
    return core::Status::Error("localizer: the LiDAR rate must be > 0 Hz");
  }
  auto impl = std::make_unique<LocalizerImpl>();
  impl->options = options;
  if (options.wheel_variance_m2_per_m > 0.0) {
    impl->options.noise = OdometryNoiseFromWheelVariance(
        options.wheel_variance_m2_per_m, setup.drive.track_m, options.lateral_variance_m2_per_m);
  }
  impl->options.smoother.track_m = setup.drive.track_m;
  impl->selector = KeyframeSelector(options.keyframes);
  const bool floor =
      options.mode == LocalizerMode::kLines || options.mode == LocalizerMode::kMapping;
  if (floor) {
    SmootherOptions smoother = impl->options.smoother;
    smoother.mode = options.mode == LocalizerMode::kMapping ? SmootherMode::kMapping
                                                            : SmootherMode::kLocalization;
    if (core::Status s = smoother.Validate(); !s.ok()) return s.WithContext("localizer smoother");
    Atlas atlas = options.mode == LocalizerMode::kMapping ? Atlas() : setup.atlas;
    if (core::Status s = atlas.Validate(); !s.ok()) return s.WithContext("localizer atlas");
    for (const AtlasLine& line : atlas.lines) {
      if (core::IsFaceKind(line.kind)) impl->walls.lines.push_back(line);
    }
    impl->smoother = std::make_unique<SlidingWindowSmoother>(smoother, std::move(atlas));
  }
  if (options.track_floor_texture) impl->flow_tracker.emplace(options.texture_flow);
  if (needs_lidar) impl->lidar = std::make_unique<LidarStage>(*setup.lidar, impl->options);
  if (needs_lidar && options.mode == LocalizerMode::kMapping) {
    // The joint solve's wheel factors take the localizer's odometry noise
    // (a --wheel-variance override included).
    AtlasMapperOptions mapper_options = options.mapper;
    mapper_options.odometry_noise = impl->options.noise;
    impl->mapper = std::make_unique<AtlasMapper>(mapper_options);
    AtlasMapper* mapper = impl->mapper.get();
    if (!setup.atlas.lines.empty() || !setup.atlas.junctions.empty()) {
      if (core::Status s = mapper->SetSurveyedLandmarks(setup.atlas); !s.ok()) {
        return s.WithContext("localizer");
      }
    }
    impl->lidar->SetScanSink(
        [mapper](double stamp_s, const core::SE2& T_odom_base, const lidar::ScanPoints& points) {
          // A scan the SLAM refuses (stamps not increasing) is counted in
          // its report; mapping goes on.
          (void)mapper->AddScan(stamp_s, T_odom_base, points);
        });
  }
  impl->setup = std::move(setup);
  return impl;
}

core::Status LocalizerImpl::SetInitialPose(double stamp_s, const core::SE2& T_map_base,
                                           const core::Matrix3& covariance) {
  if (!std::isfinite(stamp_s) || !std::isfinite(T_map_base.x()) || !std::isfinite(T_map_base.y()) ||
      !std::isfinite(T_map_base.yaw())) {
    return core::Status::Error("initial pose: expected a finite stamp, x, y and yaw");
  }
  if (!core::IsCovariance(covariance)) {
    return core::Status::Error(
        "initial pose: expected a symmetric positive definite 3x3 covariance (x, y, yaw)");
  }
  // The newest wheel reading's time tells whether the stamp is on its clock.
  std::optional<double> newest_s = last_reading_s;
  if (started) newest_s = std::max(newest_s.value_or(current.stamp_s), current.stamp_s);
  if (newest_s && stamp_s > *newest_s + options.max_sensor_lead_s) {
    ++counters.initial_poses_dropped_ahead;
    return core::Status::Error(
        "initial pose: stamped " + std::to_string(stamp_s - *newest_s) +
        " s after the newest wheel reading (max_sensor_lead_s " +
        std::to_string(options.max_sensor_lead_s) +
        "): not the odometry's clock; dropped (stamp it on the odometry's clock)");
  }
  if (started) return Restart({stamp_s, T_map_base, covariance});
  relocalizer.reset();
  relocalizer_odometry.reset();
  Start(stamp_s, T_map_base, covariance);
  return core::Status::Ok();
}

core::Status LocalizerImpl::RequestRelocalization() {
  if (options.mode != LocalizerMode::kLines) {
    return core::Status::Error("relocalization needs an atlas to recognize: the lines mode");
  }
  if (started) return core::Status::Error("relocalization: the localizer has already started");
  relocalizer = std::make_unique<Relocalizer>(setup.atlas, options.relocalizer);
  relocalizer_odometry.emplace(setup.drive, options.noise);
  return core::Status::Ok();
}

void LocalizerImpl::Start(double stamp_s, const core::SE2& T_map_base,
                          const core::Matrix3& covariance) {
  started = true;
  T_map_start = T_map_base;
  T_reinit = core::SE2();
  odometry.emplace(setup.drive, options.noise);
  // Dead reckoning carries the start's uncertainty; the smoother has its own prior.
  if (!smoother) odometry->Reset(core::SE2(), covariance);
  current = {stamp_s, T_map_base, covariance};
  keyframe = current;
  T_odom_keyframe = T_map_base;
  history.assign(1, current);
  odometry_history.assign(1, {stamp_s, odometry->T_odom_base(), odometry->covariance()});
  pending_pose.reset();
  if (smoother) smoother->Initialize(stamp_s, T_map_base, covariance);
  if (lidar) lidar->Start(stamp_s, T_map_base);
  if (mapper) mapper->SetAnchor(T_map_base, covariance);
  if (pending && pending->stamp_s < stamp_s - kSameInstantS) {
    ++counters.frames_dropped_late;
    pending.reset();
  }
}

std::optional<KeyframeOutput> LocalizerImpl::AddWheelReading(
    const core::WheelEncoderReading& source) {
  ++counters.wheel_readings;
  const bool finite_increments =
      std::isfinite(source.left_delta_rad) && std::isfinite(source.right_delta_rad);
  if (!std::isfinite(source.stamp_s) || !finite_increments) {
    ++counters.wheel_dropped_non_finite;
    odometry_fault_pending = true;  // the odometry is unknown until the next good reading
    // A finite stamp still tells the time: the estimate coasts over it.
    if (!std::isfinite(source.stamp_s)) return std::nullopt;
    const double stamp_s = source.stamp_s + clock_offset_s;
    if (last_reading_s && !(stamp_s > *last_reading_s)) return std::nullopt;
    return Coast(stamp_s);
  }
  core::WheelEncoderReading r = source;
  r.stamp_s += clock_offset_s;
  if (last_reading_s && !(r.stamp_s > *last_reading_s)) return BehindReading(r);
  jump_run.clear();  // in order again: the out-of-order readings were stray, not a jump
  return TakeReading(r);
}

std::optional<KeyframeOutput> LocalizerImpl::Coast(double stamp_s) {
  if (!started || !last_reading_s || !(options.max_coast_s > 0.0)) return std::nullopt;
  const double dt_s = stamp_s - *last_reading_s;
  const double since_s = coasting ? coast_since_s : *last_reading_s;
  if (stamp_s - since_s > options.max_coast_s || dt_s > options.max_odometry_gap_s) {
    coasting = true;  // too long: the motion is a gap when good readings return
    coast_since_s = since_s;
    return std::nullopt;
  }
  coasting = true;
  coast_since_s = since_s;
  ++counters.wheel_coasted;
  // The wheel speeds of the last good reading, and a speed error that grows
  // linearly with the time since it (variance (sigma_v T)^2 at T).
  core::WheelEncoderReading guess{stamp_s, last_left_radps * dt_s, last_right_radps * dt_s};
  const double t1 = stamp_s - coast_since_s, t0 = t1 - dt_s;
  WidenByUnknownMotion(t1 * t1 - t0 * t0);
  return Advance(guess, *last_reading_s);
}

void LocalizerImpl::WidenByUnknownMotion(double seconds2) {
  const double v = options.odometry_gap_speed_mps, w = options.odometry_gap_yaw_rate_radps;
  OdometryIncrement unknown;
  unknown.covariance = core::Vector3(v * v, v * v, w * w).asDiagonal() * seconds2;
  odometry->Integrate(unknown);
}

std::optional<KeyframeOutput> LocalizerImpl::BehindReading(const core::WheelEncoderReading& r) {
  const bool duplicate = std::any_of(recent_stamps.begin(), recent_stamps.end(), [&](double t) {
    return std::abs(t - r.stamp_s) <= kSameInstantS;
  });
  if (duplicate) {
    ++counters.wheel_dropped_duplicate;
    return std::nullopt;
  }
  if (*last_reading_s - r.stamp_s <= options.reorder_tolerance_s) {
    // Its interval lies before the newest reading's: the motion joins the next one.
    late_left_rad += r.left_delta_rad;
    late_right_rad += r.right_delta_rad;
    recent_stamps.push_back(r.stamp_s);
    ++counters.wheel_late_merged;
    return std::nullopt;
  }
  // Counted as dropped until a run of them reveals a jump (then taken after all).
  ++counters.wheel_dropped_out_of_order;
  if (!jump_run.empty() && !(r.stamp_s > jump_run.back().stamp_s)) jump_run.clear();
  jump_run.push_back(r);
  if (static_cast<int>(jump_run.size()) < options.clock_jump_readings) return std::nullopt;
  counters.wheel_dropped_out_of_order -= static_cast<long>(jump_run.size());
  // The clock jumped back: continue the localizer's time from the newest
  // reading, one mean reading interval of the run later.
  const double interval_s = (jump_run.back().stamp_s - jump_run.front().stamp_s) /
                            static_cast<double>(jump_run.size() - 1);
  const double shift_s = *last_reading_s + interval_s - jump_run.front().stamp_s;
  clock_offset_s += shift_s;
  ++counters.clock_jumps;
  recent_stamps.clear();
  std::vector<core::WheelEncoderReading> run = std::move(jump_run);
  jump_run.clear();
  std::optional<KeyframeOutput> out;
  for (core::WheelEncoderReading& reading : run) {
    reading.stamp_s += shift_s;
    std::optional<KeyframeOutput> k = TakeReading(reading);
    if (k) {
      // Only one output per call: keep the newest (the earlier ones are in the counters).
      out = std::move(k);
    }
  }
  return out;
}

void LocalizerImpl::ToSourceTime(KeyframeOutput& k) const {
  const double d = clock_offset_s;
  if (d == 0.0) return;
  k.stamp_s -= d;
  k.pose.stamp_s -= d;
  k.predicted.stamp_s -= d;
  if (k.frame_stamp_s) *k.frame_stamp_s -= d;
  k.floor.stamp_s -= d;
  if (k.smoother) k.smoother->stamp_s -= d;
  if (k.lidar) k.lidar->stamp_s -= d;
}

std::optional<KeyframeOutput> LocalizerImpl::TakeReading(core::WheelEncoderReading r) {
  if (odometry_fault_pending) {
    last_odometry_fault_s = r.stamp_s;
    odometry_fault_pending = false;
  }
  r.left_delta_rad += late_left_rad;
  r.right_delta_rad += late_right_rad;
  late_left_rad = late_right_rad = 0.0;
  recent_stamps.push_back(r.stamp_s);
  while (recent_stamps.size() > 256 ||
         (recent_stamps.size() > 1 &&
          recent_stamps.front() < r.stamp_s - options.reorder_tolerance_s - kSameInstantS)) {
    recent_stamps.pop_front();
  }
  const std::optional<double> previous_s = last_reading_s;
  const double gap_s = previous_s ? r.stamp_s - *previous_s : 0.0;
  // Frozen encoders: exactly no motion right after driving faster than
  // frozen_speed_mps, a deceleration no vehicle makes in one reading. Such
  // readings are dropped, the estimate coasting over them (Coast), until the
  // wheels report motion again.
  const bool still = r.left_delta_rad == 0.0 && r.right_delta_rad == 0.0;
  if (still && (odometry_frozen || (gap_s > 0.0 && last_speed_mps > options.frozen_speed_mps))) {
    odometry_frozen = true;
    last_odometry_fault_s = r.stamp_s;
    ++counters.wheel_dropped_frozen;
    return Coast(r.stamp_s);
  }
  odometry_frozen = false;
  const bool after_coasting = coasting;
  coasting = false;
  if (gap_s > 0.0 && gap_s <= options.max_odometry_gap_s && !after_coasting && wheel_speeds_known &&
      options.slip_speed_difference_change_mps > 0.0 && IsWheelSlip(r, gap_s)) {
    ++counters.wheel_dropped_slip;
    return Coast(r.stamp_s);
  }
  if (gap_s > 0.0) {
    const double ds_m = 0.5 * (setup.drive.LeftRadius() * r.left_delta_rad +
                               setup.drive.RightRadius() * r.right_delta_rad);
    last_speed_mps = std::abs(ds_m) / gap_s;
    last_left_radps = r.left_delta_rad / gap_s;
    last_right_radps = r.right_delta_rad / gap_s;
    wheel_speeds_known = true;
  }
  return Advance(r, previous_s);
}

bool LocalizerImpl::IsWheelSlip(const core::WheelEncoderReading& r, double gap_s) const {
  const double left_change_mps =
      setup.drive.LeftRadius() * (r.left_delta_rad / gap_s - last_left_radps);
  const double right_change_mps =
      setup.drive.RightRadius() * (r.right_delta_rad / gap_s - last_right_radps);
  return std::abs(right_change_mps - left_change_mps) > options.slip_speed_difference_change_mps;
}

std::optional<KeyframeOutput> LocalizerImpl::Advance(const core::WheelEncoderReading& r,
                                                     std::optional<double> previous_s) {
  const double gap_s = previous_s ? r.stamp_s - *previous_s : 0.0;
  if (gap_s > options.max_odometry_gap_s) ++counters.odometry_gaps;
  last_reading_s = r.stamp_s;
  if (relocalizer && !relocalizer_done_) {
    if (previous_s) return Relocalize(r);
    return std::nullopt;
  }
  if (!started) {
    ++counters.wheel_before_start;
    return std::nullopt;
  }
  if (r.stamp_s <= current.stamp_s) return std::nullopt;  // at or before the start
  if (gap_s > options.max_odometry_gap_s) {
    WidenByUnknownMotion(gap_s * gap_s);  // the motion over the gap is unknown
  }

  // The frame whose turn it is: the newest one up to this reading. Inside
  // the reading's interval it splits the reading (constant wheel speeds).
  std::optional<PendingFrame> frame;
  if (pending && pending->stamp_s <= r.stamp_s + kSameInstantS) {
    frame = std::move(pending);
    pending.reset();
  }
  const double from_s = std::max(previous_s.value_or(current.stamp_s), current.stamp_s);
  if (frame && frame->stamp_s > from_s + kSameInstantS &&
      frame->stamp_s < r.stamp_s - kSameInstantS) {
    const double fraction = (frame->stamp_s - from_s) / (r.stamp_s - from_s);
    const double frame_s = frame->stamp_s;
    Integrate(r, fraction, frame_s);
    std::optional<KeyframeOutput> out = Step(frame_s, std::move(frame));
    Integrate(r, 1.0 - fraction, r.stamp_s);
    std::optional<KeyframeOutput> late = Step(r.stamp_s, std::nullopt);
    return out ? out : late;
  }
  Integrate(r, 1.0, r.stamp_s);
  return Step(r.stamp_s, std::move(frame));
}

void LocalizerImpl::Integrate(const core::WheelEncoderReading& r, double fraction, double stamp_s) {
  const OdometryIncrement increment = odometry->Integrate(
      WheelAngleIncrement{fraction * r.left_delta_rad, fraction * r.right_delta_rad});
  path_length_m += std::abs(increment.distance_m);
  if (lidar) lidar->AddOdometry(stamp_s, T_map_start * odometry->T_odom_base(), &counters);
}

std::optional<KeyframeOutput> LocalizerImpl::Step(double stamp_s,
                                                  std::optional<PendingFrame> frame) {
  const RelativeMotion& since = odometry->SinceKeyframe();
  const bool moved = selector.IsKeyframeDue(since.T_start_end);
  std::optional<KeyframeOutput> out;
  switch (options.mode) {
    case LocalizerMode::kOdometry:
    case LocalizerMode::kLidar: {
      if (frame) ++counters.frames_skipped;
      if (!moved) break;
      const double cpu_before_s = core::ThreadCpuSeconds();
      odometry->StartKeyframe();
      KeyframeOutput k;
      k.stamp_s = stamp_s;
      k.T_odom_base = odometry->T_odom_base();
      k.predicted = {stamp_s, DeadReckoning(), odometry->covariance()};
      k.pose = k.predicted;
      if (options.mode == LocalizerMode::kLidar) {
        lidar::ScanOdometryKeyframe scan = lidar->Keyframe(stamp_s, &counters);
        CountLidar(scan);
        k.pose = {stamp_s, scan.T_odom_base, core::Matrix3::Zero()};
        k.has_covariance = false;
        k.lidar = std::move(scan);
      }
      keyframe = k.pose;
      T_odom_keyframe = k.predicted.T_map_base;
      k.update_cpu_s = core::ThreadCpuSeconds() - cpu_before_s;
      out = std::move(k);
      break;
    }
    case LocalizerMode::kLines:
    case LocalizerMode::kMapping: {
      const bool blind = since.path_length_m >= options.blind_keyframe_m;
      // A vehicle without a camera (the LiDAR's wall lines alone) keyframes on motion.
      const bool lidar_only = !setup.camera && lidar != nullptr;
      if (frame && !moved) ++counters.frames_skipped;
      if ((frame && moved) || blind || (lidar_only && moved)) {
        out = FloorKeyframe(stamp_s, std::move(frame));
      }
      break;
    }
  }
  if (out) {
    out->index = keyframe_index++;
    out->sensors = Sensors();
    ++counters.keyframes;
  }
  UpdateCurrent(stamp_s);
  if (pending_pose && pending_pose->stamp_s <= stamp_s + kSameInstantS) {
    const PoseEstimate given = *pending_pose;
    Reinitialize(given);
  }
  return out;
}

std::optional<ConvertedObservations> LocalizerImpl::Observe(PendingFrame& frame, double stamp_s) {
  if (frame.observations) {
    ConvertedObservations seen = std::move(*frame.observations);
    seen.observations.stamp_s = stamp_s;
    if (flow_tracker && seen.bev) flow_tracker->Track(*seen.bev, &seen.observations);
    seen.bev.reset();
    return seen;
  }
  if (!frame.load || !setup.camera) return std::nullopt;
  const cv::Mat grey = frame.load();
  if (grey.empty()) return std::nullopt;
  core::Result<ConvertedObservations> seen =
      setup.camera->Observe(grey, stamp_s, &bev, &extraction_scratch);
  if (!seen.ok()) return std::nullopt;
  if (flow_tracker) flow_tracker->Track(grey, *setup.camera, &seen->observations);
  return std::move(seen).value();
}

std::optional<KeyframeOutput> LocalizerImpl::FloorKeyframe(double stamp_s,
                                                           std::optional<PendingFrame> frame) {
  const double cpu_before_s = core::ThreadCpuSeconds();
  KeyframeOutput k;
  k.stamp_s = stamp_s;
  k.T_odom_base = odometry->T_odom_base();
  ConvertedObservations converted;
  converted.observations.stamp_s = stamp_s;
  if (frame) {
    std::optional<ConvertedObservations> seen = Observe(*frame, stamp_s);
    if (seen) {
      converted = std::move(*seen);
      ++counters.frames_used;
      last_frame_used_s = stamp_s;
      k.frame_stamp_s = frame->stamp_s;
    } else {
      ++counters.frames_unreadable;
    }
  }
  k.lines_dropped = converted.dropped_lines;
  k.floor = converted.observations;
  const RelativeMotion motion = odometry->StartKeyframe();
  k.predicted = PropagateFromKeyframe(smoother->Latest(), motion, stamp_s);
  std::optional<RelativePoseMeasurement> relative;
  if (lidar) {
    lidar::ScanOdometryKeyframe scan = lidar->Keyframe(stamp_s, &counters);
    CountLidar(scan);
    relative = scan.relative;
    k.lidar = std::move(scan);
    if (mapper) {
      mapper->AddKeyframe(stamp_s, lidar->OdometryAt(stamp_s), converted.observations,
                          options.use_wall_lines ? lidar->WallObservations(stamp_s)
                                                 : std::vector<LineObservation>());
    }
    if (options.use_wall_lines && options.mode == LocalizerMode::kLines) {
      const std::vector<LineObservation> seen = lidar->WallObservations(stamp_s);
      WallCounts counts;
      counts.observed = static_cast<int>(seen.size());
      for (const Match& m : AssociateLines(seen, walls, k.predicted.T_map_base,
                                           k.predicted.covariance, options.smoother.association)) {
        counts.ambiguous += m.ambiguous;
        counts.used += m.landmark >= 0;
      }
      counters.walls_observed += counts.observed;
      counters.walls_used += counts.used;
      counters.walls_ambiguous += counts.ambiguous;
      k.walls = counts;
      converted.observations.lines.insert(converted.observations.lines.end(), seen.begin(),
                                          seen.end());
    }
  }
  core::Result<KeyframeHealth> health =
      smoother->AddKeyframe(stamp_s, motion, converted.observations, relative);
  if (!health.ok()) {
    ++counters.solve_failures;
    k.error = health.message();
  } else {
    counters.lines_used += health->lines_used;
    counters.lines_rejected += health->lines_rejected;
    if (options.smoother.upkeep.enabled && options.mode == LocalizerMode::kLines) {
      counters.landmarks_born += health->landmarks_added;
      counters.landmarks_retired += health->landmarks_retired;
    }
    counters.solves_unconverged += health->converged ? 0 : 1;
    k.smoother = *health;
  }
  counters.lines_dropped += converted.dropped_lines;
  k.pose = smoother->Latest();
  k.update_cpu_s = core::ThreadCpuSeconds() - cpu_before_s;
  return k;
}

void LocalizerImpl::CountLidar(const lidar::ScanOdometryKeyframe& k) {
  ++counters.lidar_keyframes;
  counters.lidar_degenerate += k.degenerate;
  counters.lidar_fisher_degenerate += k.information.degenerate;
  counters.lidar_aliased += k.aliasing.aliased;
  counters.lidar_with_relative += k.relative.has_value();
  if (k.scans_since_previous > 0) last_scan_match_s = k.stamp_s;
}

void LocalizerImpl::UpdateCurrent(double stamp_s) {
  if (smoother) {
    current = PropagateFromKeyframe(smoother->Latest(), odometry->SinceKeyframe(), stamp_s);
  } else {
    // Dead reckoning (or the LiDAR estimate) composed with the odometry since.
    const core::SE2 T_map_odom = DeadReckoning();
    current = {
        stamp_s, keyframe.T_map_base * T_odom_keyframe.Between(T_map_odom),
        options.mode == LocalizerMode::kOdometry ? odometry->covariance() : core::Matrix3::Zero()};
  }
  history.push_back(current);
  odometry_history.push_back({stamp_s, odometry->T_odom_base(), odometry->covariance()});
  while (history.size() > 2 && history[1].stamp_s < stamp_s - options.odometry_history_s) {
    history.pop_front();
    odometry_history.pop_front();
  }
}

std::optional<KeyframeOutput> LocalizerImpl::Relocalize(const core::WheelEncoderReading& r) {
  relocalizer_odometry->Integrate(WheelAngleIncrement{r.left_delta_rad, r.right_delta_rad});
  if (!pending || pending->stamp_s > r.stamp_s + kSameInstantS) return std::nullopt;
  PendingFrame frame = std::move(*pending);
  pending.reset();
  const RelativeMotion motion = relocalizer_odometry->StartKeyframe();
  std::optional<ConvertedObservations> seen = Observe(frame, r.stamp_s);
  if (seen) {
    ++counters.frames_used;
  } else {
    ++counters.frames_unreadable;
  }
  const std::optional<PoseEstimate> pose = relocalizer->AddFrame(
      r.stamp_s, motion,
      seen ? seen->observations : FloorObservations{r.stamp_s, {}, {}, std::nullopt, nullptr, {}});
  if (!pose) return std::nullopt;
  relocalized = *pose;
  relocalizer_odometry.reset();
  auto keep = std::move(relocalizer);  // its status stays readable
  Start(pose->stamp_s, pose->T_map_base, pose->covariance);
  relocalizer = std::move(keep);
  relocalizer_done_ = true;
  return std::nullopt;
}

void LocalizerImpl::AddFrame(double stamp_s, Localizer::FrameLoader load,
                             std::optional<ConvertedObservations> observations) {
  ++counters.frames;
  const bool waiting = !started && !(relocalizer && !relocalizer_done_);
  if (!std::isfinite(stamp_s) || stamp_s <= last_frame_s) {
    ++counters.frames_unreadable;
    return;
  }
  if (last_reading_s && stamp_s > *last_reading_s + options.max_sensor_lead_s) {
    ++counters.frames_dropped_ahead;
    return;
  }
  last_frame_s = stamp_s;
  if (waiting || (last_reading_s && stamp_s < *last_reading_s - options.max_frame_lag_s)) {
    ++counters.frames_dropped_late;
    return;
  }
  if (pending) ++counters.frames_superseded;
  pending = PendingFrame{stamp_s, std::move(load), std::move(observations)};
}

void LocalizerImpl::AddScan(core::LaserScan scan) {
  if (!lidar) return;
  if (last_reading_s && std::isfinite(scan.stamp_s) &&
      scan.stamp_s > *last_reading_s + options.max_sensor_lead_s) {
    ++counters.scans;
    ++counters.scans_dropped_ahead;
    return;
  }
  lidar->AddScan(std::move(scan), &counters);
}

std::optional<PoseEstimate> LocalizerImpl::PoseAt(double stamp_s) const {
  if (!started || history.empty() || stamp_s < history.front().stamp_s - kSameInstantS ||
      stamp_s > history.back().stamp_s + kSameInstantS) {
    return std::nullopt;
  }
  const auto it = std::lower_bound(history.begin(), history.end(), stamp_s,
                                   [](const PoseEstimate& p, double t) { return p.stamp_s < t; });
  if (it == history.begin()) return *it;
  if (it == history.end()) return history.back();
  const PoseEstimate& b = *it;
  const PoseEstimate& a = *(it - 1);
  const double f = (stamp_s - a.stamp_s) / (b.stamp_s - a.stamp_s);
  return PoseEstimate{stamp_s, core::InterpolateSE2(a.T_map_base, b.T_map_base, f), b.covariance};
}

SensorState LocalizerImpl::Sensors() const {
  SensorState s;
  const double now_s = last_reading_s.value_or(0.0);
  const bool uses_camera = smoother != nullptr;
  if (std::isfinite(last_frame_used_s)) s.camera_age_s = now_s - last_frame_used_s;
  if (std::isfinite(last_scan_match_s)) s.lidar_age_s = now_s - last_scan_match_s;
  s.camera_ok = uses_camera && s.camera_age_s >= 0.0 && s.camera_age_s <= options.stale_after_s;
  s.lidar_ok = lidar && s.lidar_age_s >= 0.0 && s.lidar_age_s <= options.stale_after_s;
  s.odometry_frozen = odometry_frozen;
  s.odometry_ok =
      !odometry_frozen && !coasting && !(now_s - last_odometry_fault_s <= options.stale_after_s);
  const bool wants_camera = uses_camera;
  const bool wants_lidar = lidar != nullptr;
  if ((!wants_camera || s.camera_ok) && (!wants_lidar || s.lidar_ok) && s.odometry_ok) {
    s.degraded_mode = "full";
  } else {
    // What the estimate rests on now, e.g. "lidar+odometry" (the camera is
    // blind), "lines+lidar" (the odometry is frozen or not finite).
    for (const auto& [ok, name] : {std::pair{s.camera_ok, "lines"}, std::pair{s.lidar_ok, "lidar"},
                                   std::pair{s.odometry_ok, "odometry"}}) {
      if (!ok) continue;
      if (!s.degraded_mode.empty()) s.degraded_mode += "+";
      s.degraded_mode += name;
    }
    if (s.degraded_mode.empty()) s.degraded_mode = "none";
  }
  return s;
}

}  // namespace groundline::localization::internal
