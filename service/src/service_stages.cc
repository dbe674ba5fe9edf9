// The service's threads: the camera input, the camera stage and the estimator.
#include "service_impl.h"

#include "groundline/io/image_file.h"

namespace groundline::service {

void Service::Impl::PushFrame(FrameJob job) {
  job.seq = input_seq++;
  const double previous_s = frame_watermark_s.exchange(job.stamp_s);
  if (previous_s > -1e299 && job.stamp_s > previous_s) {
    const double dt = job.stamp_s - previous_s;
    const double period = frame_period_s.load();
    frame_period_s.store(period > 0.0 ? 0.9 * period + 0.1 * dt : dt);
  }
  frame_wall_ticks.store(Clock::now().time_since_epoch().count());
  {
    std::lock_guard<std::mutex> lock(pending_mutex);
    pending_frames.insert(job.stamp_s);
  }
  if (config.replay_speed == 0.0) {
    frames->PushWait(std::move(job));  // as fast as possible: no frame is lost
  } else if (std::optional<FrameJob> dropped = frames->Push(std::move(job))) {
    ++camera_dropped;
    ReleasePending(dropped->stamp_s);
  }
}

void Service::Impl::CameraInput(const std::atomic<bool>& done) {
  std::unique_ptr<io::FrameSource> source;
  // A live camera stops with the inputs; a recorded folder plays to its end.
  while (!done.load() || (source && !source->IsLive())) {
    if (!source) {
      core::Result<std::unique_ptr<io::FrameSource>> opened =
          io::OpenFrameSource(config.camera_uri);
      if (!opened.ok()) {
        ++camera_source_errors;  // unplugged: try again in a second
        std::this_thread::sleep_for(std::chrono::seconds(1));
        continue;
      }
      source = std::move(opened).value();
      ++camera_reopens;
    }
    core::Result<std::optional<io::Frame>> frame = source->Next(1.0);
    if (!frame.ok()) {
      ++camera_source_errors;
      source.reset();
      continue;
    }
    if (!*frame) break;  // a folder's last frame
    // A recorded folder follows the replay's clock; a live camera is its own.
    while (!source->IsLive() && !done.load() && replay_now_s.load() < (*frame)->stamp_s) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    FrameJob job;
    job.stamp_s = (*frame)->stamp_s;
    job.grey = std::move((*frame)->grey);
    job.arrived = Clock::now();
    PushFrame(std::move(job));
  }
}

void Service::Impl::CameraStage() {
  const double cpu_start_s = ThreadCpuSeconds();
  Clock::time_point last_bev = Clock::now() - std::chrono::seconds(1);
  // Frame-sized buffers kept from frame to frame: the decoded file, the BEV
  // and the extractor's images are allocated once, not per frame.
  io::GreyImageFileReader reader;
  cv::Mat decoded;
  cv::Mat bev;
  perception::ExtractionScratch scratch;
  while (!frames->closed_and_empty()) {
    std::optional<FrameJob> job = frames->Pop(std::chrono::milliseconds(20));
    if (!job) continue;
    // The motion since the last keyframe extrapolated to the frame's time.
    const KeyframeSelector::Options& due = localizer->options().keyframes;
    // Judged only for a frame near the estimator's time: one far behind it
    // is on a clock that stepped back (the estimator has not got there yet).
    // A replay as fast as possible extracts every frame: how far the
    // estimator has got when the frame comes up depends on the machine's
    // load, and that run's results must not (the localizer still skips the
    // frames that no keyframe uses).
    const double behind_s = since_stamp_s.load() - job->stamp_s;
    const double ahead_s = std::max(0.0, -behind_s);
    if (config.replay_speed > 0.0 && behind_s <= localizer->options().max_frame_lag_s &&
        since_keyframe_m.load() + speed_mps.load() * ahead_s <
            not_due_fraction * due.min_translation_m &&
        since_keyframe_rad.load() + yaw_rate_radps.load() * ahead_s <
            not_due_fraction * due.min_rotation_rad) {
      ++camera_not_due;
      ReleasePending(job->stamp_s);
      continue;
    }
    std::optional<loc::KeyframeMountCalibration::MountUpdate> mount_update;
    {
      std::lock_guard<std::mutex> lock(mount_mutex);
      mount_update.swap(pending_mount);
    }
    if (mount_update && camera) {
      core::Result<loc::FloorFrontEnd> rebuilt =
          camera->WithMount(mount_update->mount, mount_update->covariance, mount_update->observed);
      if (rebuilt.ok()) {
        camera = std::make_shared<const loc::FloorFrontEnd>(std::move(rebuilt).value());
        ++mount_rebuilds;
      } else {
        ++mount_rebuild_failures;
      }
    }
    cv::Mat grey;
    if (job->black && camera) {
      grey = cv::Mat::zeros(camera->image_height_px(), camera->image_width_px(), CV_8UC1);
    } else if (!job->grey.empty()) {
      grey = job->grey;
    } else if (!job->corrupt && reader.Read(job->path, &decoded).ok()) {
      grey = decoded;
    }
    // A camera delivers decoded frames: the latency counts from here.
    job->arrived = Clock::now();
    core::Result<loc::ConvertedObservations> seen =
        grey.empty() || !camera ? core::Status::Error("unreadable frame " + job->path.string())
                                : camera->Observe(grey, job->stamp_s, &bev, &scratch);
    if (seen.ok() && localizer->options().track_floor_texture) {
      loc::BevFrame texture{cv::Mat(), cv::Mat(), camera->remap().grid(), camera->mount()};
      if (camera->TextureBev(grey, &texture).ok()) seen->bev = std::move(texture);
    }
    if (seen.ok()) {
      ++camera_processed;
      if (Clock::now() - last_bev > std::chrono::milliseconds(500)) {
        last_bev = Clock::now();
        std::vector<std::uint8_t> png = DrawBevPng(bev, *camera, seen->observations);
        std::lock_guard<std::mutex> lock(status_mutex);
        bev_png = std::move(png);
      }
      // Its own queue, ahead of any backlog of readings; the frame stays
      // pending until the estimator has taken it.
      observed.PushWait(Observed{std::move(seen).value(), job->arrived, job->seq});
    } else {
      ++camera_unreadable;
      ReleasePending(job->stamp_s);
    }
  }
  std::lock_guard<std::mutex> lock(status_mutex);
  cpu_camera_s = ThreadCpuSeconds() - cpu_start_s;
}

void Service::Impl::EstimatorStage(std::ofstream& keyframes, std::ofstream& odometry,
                                   std::ofstream& health) {
  const double cpu_start_s = ThreadCpuSeconds();
  std::deque<HeldReading> held;
  std::optional<Clock::time_point> last_frame_arrival;
  // As fast as possible there is no deadline: a reading waits for its frame.
  const auto wait = config.replay_speed == 0.0
                        ? Clock::duration::max()
                        : std::chrono::duration_cast<Clock::duration>(
                              std::chrono::duration<double>(config.max_frame_wait_s));
  const loc::LocalizerMode mode = localizer->options().mode;
  auto apply = [&](const HeldReading& held_reading) {
    const core::WheelEncoderReading& r = held_reading.reading;
    core::SE2 T_odom_base = held_reading.T_odom_base.value_or(core::SE2());
    bool have_odom_frame = held_reading.T_odom_base.has_value();
    if (!have_odom_frame && dds_outputs) {
      // The service's own odom frame: the wheel readings integrated from the
      // first one (whose deltas predate the stream), non-finite ones skipped.
      if (!own_odom) {
        own_odom.emplace(drive, loc::OdometryNoiseParams{});
      } else if (std::isfinite(r.left_delta_rad) && std::isfinite(r.right_delta_rad)) {
        own_odom->Integrate(loc::WheelAngleIncrement{r.left_delta_rad, r.right_delta_rad});
      }
      T_odom_base = own_odom->T_odom_base();
      have_odom_frame = true;
    }
    const double before_s = localizer->started() ? localizer->Current().stamp_s : -1.0;
    std::optional<loc::KeyframeOutput> k = localizer->AddWheelReading(r);
    newest_reading_s.store(r.stamp_s);
    std::lock_guard<std::mutex> lock(status_mutex);
    if (!first_reading_s) first_reading_s = r.stamp_s;
    const double data_s = r.stamp_s - *first_reading_s;
    if (rss_samples.empty() || data_s >= rss_samples.back().first + 600.0) {
      rss_samples.emplace_back(data_s, ResidentMb());
    }
    const bool moved = localizer->started() && localizer->Current().stamp_s != before_s;
    if (moved) {
      pose = localizer->Current();
      odometry << core::FormatTumLine({pose.stamp_s, pose.T_map_base, std::nullopt});
      ++odometry_out;
    }
    if (k) {
      nlohmann::ordered_json line = loc::KeyframeJson(*k, mode);
      if (self_calibration) {
        if (self_calibration->AddKeyframe(*k) && !mount_estimate_path.empty() &&
            !calibration::WriteMountEstimate(mount_estimate_path, {self_calibration->commissioned(),
                                                                   self_calibration->estimate()})
                 .ok()) {
          ++mount_estimate_write_failures;
        }
        if (auto update = self_calibration->DueMountUpdate(k->stamp_s)) {
          std::lock_guard<std::mutex> mount_lock(mount_mutex);
          pending_mount = std::move(update);
        }
        line.update(loc::MountEstimateJson(self_calibration->estimate(),
                                           &self_calibration->applied(),
                                           &self_calibration->observed()));
      }
      if (k->frame_stamp_s && last_frame_arrival && config.replay_speed > 0.0) {
        latency_ms.push_back(
            1e3 * std::chrono::duration<double>(Clock::now() - *last_frame_arrival).count());
        line["latency_ms"] = latency_ms.back();
      }
      const double t = k->stamp_s - replay_first_s;
      for (std::size_t i = 0; i < config.faults.size(); ++i) {
        const InjectedFault& f = config.faults[i];
        FaultTrack& track = fault_tracks[i];
        const bool full = k->sensors.degraded_mode == "full";
        if (t >= f.from_s && t < f.to_s + 5.0 && !full) track.degraded_seen = true;
        if (t >= f.to_s && full && !track.recovered_at_s) track.recovered_at_s = t;
      }
      health << line.dump() << "\n";
      health.flush();
      keyframes << core::FormatTumLine({k->pose.stamp_s, k->pose.T_map_base, std::nullopt});
      keyframes.flush();
      last_keyframe = std::move(line);
    }
    counters = localizer->counters();
    if (rate_samples.empty() || r.stamp_s >= rate_samples.back().stamp_s + 0.1) {
      rate_samples.push_back({r.stamp_s, counters.wheel_readings, counters.frames, counters.scans});
      while (rate_samples.front().stamp_s < r.stamp_s - kRateWindowS) rate_samples.pop_front();
    }
    PublishDds(moved && have_odom_frame ? &T_odom_base : nullptr, k);
    const loc::RelativeMotion since = localizer->SinceKeyframe();
    since_keyframe_m.store(since.T_start_end.translation().norm());
    since_keyframe_rad.store(std::abs(since.T_start_end.yaw()));
    if (localizer->started()) {
      const loc::PoseEstimate now = localizer->Current();
      if (const std::optional<loc::PoseEstimate> before = localizer->PoseAt(now.stamp_s - 0.1)) {
        const double dt = now.stamp_s - before->stamp_s;
        if (dt > 0.0) {
          const core::SE2 d = before->T_map_base.Between(now.T_map_base);
          speed_mps.store(d.translation().norm() / dt);
          yaw_rate_radps.store(std::abs(d.yaw()) / dt);
        }
      }
      since_stamp_s.store(now.stamp_s);
    }
  };
  std::deque<Observed> taken;  // observations in stamp order, waiting for their reading
  const double max_lag_s = localizer->options().max_frame_lag_s;
  const auto frame_expected = [&](double stamp_s) {
    const double period = frame_period_s.load();
    if (period <= 0.0) return false;
    // Stalled: no frame for three periods (at least 0.2 s), in wall time for
    // a paced or live source; as fast as possible, in the replay's data time
    // (the replay hands out every event in stamp order, so a frame not handed
    // out by then is not in the log), which keeps such a run independent of
    // the machine's load.
    const double stall_s = std::max(0.2, 3.0 * period);
    bool stalled = false;
    if (config.replay_speed == 0.0) {
      stalled = replay_now_s.load() - frame_watermark_s.load() > stall_s;
    } else {
      const Clock::duration since_frame =
          Clock::now() - Clock::time_point(Clock::duration(frame_wall_ticks.load()));
      stalled = since_frame >
                std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(stall_s));
    }
    // The next frame is due at the reading's time, and not so long ago that
    // the localizer would drop it as late.
    const double due_s = frame_watermark_s.load() + 0.9 * period;
    return !stalled && stamp_s + 1e-9 >= due_s && stamp_s - due_s <= max_lag_s;
  };
  while (!events.closed_and_empty() || !observed.closed_and_empty() || !held.empty()) {
    while (std::optional<Observed> o = observed.Pop(std::chrono::milliseconds(0))) {
      const double stamp_s = o->observations.observations.stamp_s;
      taken.push_back(std::move(*o));
      ReleasePending(stamp_s);
      if (taken.size() > kMaxObservationsWaiting) {
        taken.pop_front();  // the wheel readings have gone silent: bounded memory
        ++observations_without_odometry;
      }
    }
    std::optional<EstimatorEvent> event = events.Pop(std::chrono::milliseconds(2));
    if (event) {
      switch (event->kind) {
        case EstimatorEvent::Kind::kWheel:
          held.push_back(
              {event->wheel, event->T_odom_base, Clock::now(), std::nullopt, event->seq});
          break;
        case EstimatorEvent::Kind::kInitialPose: {
          // rt/initialpose: the start, or a re-initialization of the running
          // estimate (Localizer::SetInitialPose); an unset stamp (0) means "now".
          const io::PlanarPoseStamped& p = event->initial_pose;
          double stamp_s = p.stamp_s > 0.0 ? p.stamp_s : replay_now_s.load();
          for (auto it = held.rbegin(); p.stamp_s <= 0.0 && it != held.rend(); ++it) {
            if (it->scan) continue;
            stamp_s = it->reading.stamp_s;  // the newest reading waiting
            break;
          }
          const core::Status s = localizer->SetInitialPose(stamp_s, p.T_frame_base, p.covariance);
          std::lock_guard<std::mutex> lock(status_mutex);
          counters = localizer->counters();
          if (s.ok()) {
            ++initial_poses_applied;
            pose = localizer->Current();
          } else {
            ++initial_poses_refused;
            initial_pose_last_error = "rt/initialpose: " + s.message();
          }
          break;
        }
        case EstimatorEvent::Kind::kScan:
          if (held.empty()) {
            localizer->AddScan(std::move(event->scan));
          } else {
            HeldReading h;
            h.since = Clock::now();
            h.seq = event->seq;
            h.scan = std::move(event->scan);
            held.push_back(std::move(h));
          }
          break;
      }
    }
    // Apply the held readings whose frames are in (or that waited long
    // enough), each after the observations of its time.
    const bool closing = events.closed_and_empty();
    while (!held.empty()) {
      if (held.front().scan) {
        localizer->AddScan(std::move(*held.front().scan));
        held.pop_front();
        continue;
      }
      const core::WheelEncoderReading& reading = held.front().reading;
      const bool waiting = FramePendingAtOrBefore(reading.stamp_s, max_lag_s) ||
                           (!closing && frame_expected(reading.stamp_s));
      if (waiting && Clock::now() - held.front().since < wait) break;
      // The observations of the reading's time; one far older than the
      // reading that arrived after it is on a clock that stepped back: it
      // waits for the readings of that clock.
      const auto before_reading = [&](const Observed& o) {
        const double t = o.observations.observations.stamp_s;
        return t <= reading.stamp_s + 1e-9 &&
               (t >= reading.stamp_s - max_lag_s || o.seq < held.front().seq);
      };
      while (!taken.empty() && before_reading(taken.front())) {
        last_frame_arrival = taken.front().arrived;
        localizer->AddFloorObservations(std::move(taken.front().observations));
        taken.pop_front();
      }
      apply(held.front());
      held.pop_front();
    }
  }
  observations_without_odometry += static_cast<long>(taken.size());
  std::lock_guard<std::mutex> lock(status_mutex);
  cpu_estimator_s = ThreadCpuSeconds() - cpu_start_s;
}

}  // namespace groundline::service
