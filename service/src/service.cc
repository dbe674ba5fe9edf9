#include "groundline/service/service_state.h"
#include "service_impl.h"

#include <malloc.h>

#include <condition_variable>

namespace groundline::service {

Service::Service(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Service::~Service() {
  if (impl_->http_thread.joinable()) {
    impl_->http.stop();
    impl_->http_thread.join();
  }
}
int Service::http_port() const { return impl_->port; }

core::Result<std::unique_ptr<Service>> Service::Create(const ServiceConfig& config) {
  if (core::Status s = config.Validate(); !s.ok()) return s;
  auto impl = std::make_unique<Impl>();
  impl->config = config;
  // DDS inputs are live: frames never wait for room, readings wait for their
  // frame at most max_frame_wait_s (the replay's pacing does not apply).
  if (config.dds_inputs.enabled) impl->config.replay_speed = 1.0;
  impl->frames =
      std::make_unique<BoundedQueue<FrameJob>>(static_cast<std::size_t>(config.camera_queue_depth));
  core::DatasetReadOptions read;
  read.check_image_files = false;
  read.load_scans = false;
  core::Result<core::Dataset> dataset = core::ReadDataset(config.replay_dataset, read);
  if (!dataset.ok()) return dataset.status();
  impl->dataset = std::move(dataset).value();
  DatasetLocalizerOptions options;
  // GCC 12 takes the move of a disengaged std::optional<Eigen::Vector2d>
  // (RelocalizerOptions::near_m) for a read of uninitialized storage.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
  options.localizer = PresetOptions(config.preset);
#pragma GCC diagnostic pop
  options.localizer.smoother.upkeep.enabled = config.keep_atlas_current;
  // The self-calibration's motion evidence: the floor's texture tracked from
  // keyframe to keyframe (the camera stage hands each frame's BEV on).
  options.localizer.track_floor_texture = config.self_calibration;
  options.front_end.bev = config.Bev();
  options.atlas_path = config.atlas;
  options.odometry_calibration_path = config.odometry_calibration;
  core::Result<DatasetSetup> setup =
      SetupFromDataset(config.replay_dataset, impl->dataset, options);
  if (!setup.ok()) return setup.status();
  // ROS stamps a LaserScan at its first ray (the dataset may say mid_sweep).
  if (config.dds_inputs.enabled && setup->setup.lidar) {
    setup->setup.lidar->stamp = core::LidarStamp::kFirstRay;
  }
  if (config.self_calibration) {
    if (!setup->camera_mount) {
      return core::Status::Error(config.replay_dataset +
                                 ": localizer.self_calibration needs the dataset's camera");
    }
    calibration::MountSelfCalibrationOptions self_calibration_options;
    if (setup->odometry_calibration) {
      self_calibration_options =
          loc::WithOdometryCalibration(self_calibration_options, *setup->odometry_calibration);
    }
    impl->self_calibration.emplace(*setup->camera_mount, self_calibration_options);
    if (setup->options.mode == loc::LocalizerMode::kLines) {
      impl->self_calibration->SetAtlas(std::make_shared<const loc::Atlas>(setup->setup.atlas),
                                       setup->options.smoother.association);
    }
  }
  impl->drive = setup->setup.drive;
  impl->camera = setup->setup.camera;
  if (impl->self_calibration) {
    // The mount is the vehicle's, not the trip's: a restart continues from
    // the saved estimate. One that cannot be used is reported, not fatal.
    impl->mount_estimate_path = config.mount_estimate.empty()
                                    ? fs::path(config.output_dir) / "mount_estimate.json"
                                    : fs::path(config.mount_estimate);
    std::error_code ec;
    if (!fs::exists(impl->mount_estimate_path, ec)) {
      impl->mount_estimate_restored = "none saved: started from the commissioned mount";
    } else {
      core::Result<calibration::SavedMountEstimate> saved =
          calibration::ReadMountEstimate(impl->mount_estimate_path);
      core::Result<std::optional<loc::KeyframeMountCalibration::MountUpdate>> restored =
          saved.ok() ? impl->self_calibration->Restore(*saved)
                     : core::Result<std::optional<loc::KeyframeMountCalibration::MountUpdate>>(
                           saved.status());
      if (!restored.ok()) {
        impl->mount_estimate_restored =
            "not restored (" + restored.message() + "): started from the commissioned mount";
      } else {
        impl->mount_estimate_restored = "restored from " + impl->mount_estimate_path.string();
        if (*restored && impl->camera) {
          core::Result<loc::FloorFrontEnd> rebuilt = impl->camera->WithMount(
              (*restored)->mount, (*restored)->covariance, (*restored)->observed);
          if (!rebuilt.ok()) return rebuilt.status().WithContext("restored mount estimate");
          impl->camera = std::make_shared<const loc::FloorFrontEnd>(std::move(rebuilt).value());
          setup->setup.camera = impl->camera;
        }
      }
    }
  }
  impl->atlas = setup->setup.atlas;
  core::Result<std::unique_ptr<loc::Localizer>> localizer =
      loc::Localizer::Create(setup->options, std::move(setup->setup));
  if (!localizer.ok()) return localizer.status();
  impl->localizer = std::move(localizer).value();

  // The start: a saved state (resume), the configured pose, relocalization,
  // or the dataset's start pose.
  const fs::path state_path = fs::path(config.output_dir) / "state.json";
  core::Status started = core::Status::Ok();
  if (config.resume && fs::exists(state_path)) {
    core::Result<SavedState> state = ReadServiceState(state_path);
    if (!state.ok()) return state.status();
    impl->resume_after_s = state->stamp_s;
    started = impl->localizer->SetInitialPose(state->stamp_s, state->T_map_base, state->covariance);
    if (!started.ok()) return started.WithContext(state_path.string());
  } else if (config.wait_for_initial_pose) {
    // Started by the first rt/initialpose (the estimator applies it).
  } else if (config.initial_pose) {
    const auto& p = *config.initial_pose;
    started = impl->localizer->SetInitialPose(
        setup->first_reading_s, core::SE2(p[0], p[1], p[2] * std::numbers::pi / 180.0),
        StartCovariance(core::StartPose{}));
  } else if (config.relocalize) {
    started = impl->localizer->RequestRelocalization();
  } else if (setup->start_pose) {
    started = impl->localizer->SetInitialPose(
        std::min(setup->first_reading_s, setup->start_pose->stamp_s), setup->start_pose->T_map_base,
        StartCovariance(*setup->start_pose));
  } else {
    return core::Status::Error(config.replay_dataset +
                               ": no start: the manifest has no start_pose; set "
                               "start.initial_pose or start.relocalize");
  }
  if (!started.ok()) return started;
  impl->pose = impl->localizer->Current();
  if (core::Status s = impl->CreateDds(); !s.ok()) return s;
  impl->atlas_json = AtlasJson(impl->atlas);

  if (config.http_enabled) {
    Impl* m = impl.get();
    m->http.Get("/health.json", [m](const httplib::Request&, httplib::Response& res) {
      res.set_content(Service::StatusJsonOf(*m).dump(), "application/json");
    });
    m->http.Get("/", [](const httplib::Request&, httplib::Response& res) {
      res.set_content(StatusPageHtml(), "text/html");
    });
    m->http.Get("/atlas.json", [m](const httplib::Request&, httplib::Response& res) {
      res.set_content(m->atlas_json, "application/json");
    });
    m->http.Get("/bev.png", [m](const httplib::Request&, httplib::Response& res) {
      std::lock_guard<std::mutex> lock(m->status_mutex);
      if (m->bev_png.empty()) {
        res.status = 404;
        return;
      }
      res.set_content(std::string(m->bev_png.begin(), m->bev_png.end()), "image/png");
    });
    m->port =
        config.http_port == 0
            ? m->http.bind_to_any_port(config.http_address)
            : (m->http.bind_to_port(config.http_address, config.http_port) ? config.http_port : -1);
    if (m->port < 0) {
      return core::Status::Error("http: cannot listen on " + config.http_address + ":" +
                                 std::to_string(config.http_port) +
                                 " (in use? set http.port, or 0 for any free port)");
    }
    m->http_thread = std::thread([m] { m->http.listen_after_bind(); });
  }
  return std::unique_ptr<Service>(new Service(std::move(impl)));
}

core::Result<nlohmann::ordered_json> Service::Run(const std::atomic<bool>& stop) {
  Impl& m = *impl_;
  const fs::path out(m.config.output_dir);
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec)
    return core::Status::Error(out.string() +
                               ": cannot create the output directory: " + ec.message());
  const bool resuming = std::isfinite(m.resume_after_s);
  int stale_lines = 0;
  if (resuming) {
    for (const auto& [name, format] :
         {std::pair{"trajectory.tum", StreamedFormat::kTum},
          std::pair{"trajectory_odometry_rate.tum", StreamedFormat::kTum},
          std::pair{"health.jsonl", StreamedFormat::kJsonLines}}) {
      core::Result<int> removed = TrimStreamedOutput(out / name, format, m.resume_after_s);
      if (!removed.ok()) return removed.status();
      stale_lines += *removed;
    }
  }
  const auto mode = std::ios::out | (resuming ? std::ios::app : std::ios::trunc);
  std::ofstream keyframes(out / "trajectory.tum", mode),
      odometry(out / "trajectory_odometry_rate.tum", mode), health(out / "health.jsonl", mode);
  if (!keyframes || !odometry || !health) {
    return core::Status::Error(out.string() + ": cannot write the run outputs");
  }
  const Clock::time_point wall_start = Clock::now();
  const double first_s =
      std::min(m.dataset.wheel_encoders.front().stamp_s,
               m.dataset.images.empty() ? 1e300 : m.dataset.images.front().stamp_s);
  // One pass lasts from the first event to one reading period after the last.
  const double period_s =
      m.dataset.wheel_encoders.back().stamp_s - first_s +
      (m.dataset.wheel_encoders.size() > 1
           ? m.dataset.wheel_encoders[1].stamp_s - m.dataset.wheel_encoders[0].stamp_s
           : 0.01);
  m.replay_first_s = first_s;
  m.fault_tracks.assign(m.config.faults.size(), {});
  std::thread camera_thread([&m] { m.CameraStage(); });
  std::atomic<bool> inputs_done{false};
  std::thread camera_input;
  if (!m.config.camera_uri.empty()) camera_input = std::thread([&] { m.CameraInput(inputs_done); });
  std::thread estimator_thread([&] { m.EstimatorStage(keyframes, odometry, health); });
  // Returns the heap's free pages to the system after every
  // kTrimDataPeriodS of sensor data (glibc's malloc_trim, which also releases
  // free pages inside the heap, not only at its top). glibc keeps large
  // blocks on the heap once one of their size has been freed, so the LiDAR
  // stage's grids and OpenCV's working buffers are reused without page
  // faults; the trim stops fragmentation from keeping a shift's peak
  // resident. Data time, not wall time: the heap churn between two trims is
  // that of the same stretch of data whether the service runs at real time
  // or replays as fast as it can (docs/service.md, "Memory over a shift").
  std::mutex trim_mutex;
  std::condition_variable trim_wake;
  bool trim_done = false;
  std::thread memory_thread([&] {
    constexpr double kTrimDataPeriodS = 10.0;
    double last_s = std::numeric_limits<double>::quiet_NaN();
    std::unique_lock<std::mutex> lock(trim_mutex);
    while (!trim_wake.wait_for(lock, std::chrono::milliseconds(100), [&] { return trim_done; })) {
      const double now_s = m.newest_reading_s.load();
      if (!(now_s >= last_s)) {  // the first reading, or a clock that stepped back
        if (std::isfinite(now_s)) last_s = now_s;
        continue;
      }
      if (now_s - last_s < kTrimDataPeriodS) continue;
      last_s = now_s;
      const Clock::time_point start = Clock::now();
      malloc_trim(0);
      const double ms = 1e3 * std::chrono::duration<double>(Clock::now() - start).count();
      std::lock_guard<std::mutex> status_lock(m.status_mutex);
      ++m.memory_trims;
      m.trim_ms_total += ms;
      m.trim_ms_max = std::max(m.trim_ms_max, ms);
    }
  });

  core::Status replayed = core::Status::Ok();
  const double cpu_start_s = ThreadCpuSeconds();
  const auto faulty = [&m, first_s](InjectedFault::Sensor sensor,
                                    double stamp_s) -> const InjectedFault* {
    for (const InjectedFault& f : m.config.faults) {
      if (f.sensor == sensor && stamp_s - first_s >= f.from_s && stamp_s - first_s < f.to_s)
        return &f;
    }
    return nullptr;
  };
  // The injected clock steps of all sensors at a data time.
  const auto clock_shift_s = [&m, first_s](double stamp_s) {
    double shift_s = 0.0;
    for (const InjectedFault& f : m.config.faults) {
      if (f.sensor == InjectedFault::Sensor::kClock && stamp_s - first_s >= f.from_s)
        shift_s += f.by_s;
    }
    return shift_s;
  };
  std::optional<EstimatorEvent> swapped;  // odometry "reorder": held for one reading
  if (m.dds_inputs) m.DdsInputLoop(stop);
  for (int pass = 0; pass < m.config.replay_loops && replayed.ok() && !stop.load() && !m.dds_inputs;
       ++pass) {
    core::Result<core::DatasetStreams> streams =
        core::DatasetStreams::Open(m.config.replay_dataset, m.dataset);
    if (!streams.ok()) {
      replayed = streams.status();
      break;
    }
    const double pass_s = pass * period_s;
    ReplayOptions options;
    options.speed = m.config.replay_speed;
    options.start_after_s = m.resume_after_s - pass_s;
    options.stop = [&stop] { return stop.load(); };
    core::Result<ReplayStats> stats = ReplayEvents(*streams, options, [&](core::DatasetEvent& e) {
      const double shift_s = pass_s + clock_shift_s(e.stamp_s);
      m.replay_now_s.store(e.stamp_s + shift_s);
      if (e.kind == core::DatasetEvent::Kind::kFrame && !m.config.camera_uri.empty()) return;
      switch (e.kind) {
        case core::DatasetEvent::Kind::kWheel: {
          EstimatorEvent event;
          event.wheel = e.wheel;
          event.wheel.stamp_s += shift_s;
          const InjectedFault* f = faulty(InjectedFault::Sensor::kOdometry, e.stamp_s);
          if (f && (f->kind == "nan" || f->kind == "frozen")) {
            const double value = f->kind == "nan" ? std::numeric_limits<double>::quiet_NaN() : 0.0;
            event.wheel.left_delta_rad = event.wheel.right_delta_rad = value;
          }
          if (f && f->kind == "duplicate") m.PushEvent(EstimatorEvent(event));
          if (f && f->kind == "reorder" && !swapped) {
            swapped = std::move(event);  // delivered after the next reading
            break;
          }
          m.PushEvent(std::move(event));
          if (swapped) {
            m.PushEvent(std::move(*swapped));
            swapped.reset();
          }
          break;
        }
        case core::DatasetEvent::Kind::kScan: {
          if (faulty(InjectedFault::Sensor::kLidar, e.stamp_s)) break;
          EstimatorEvent event;
          event.kind = EstimatorEvent::Kind::kScan;
          event.scan = std::move(e.scan);
          event.scan.stamp_s += shift_s;
          m.PushEvent(std::move(event));
          break;
        }
        case core::DatasetEvent::Kind::kFrame: {
          const InjectedFault* f = faulty(InjectedFault::Sensor::kCamera, e.stamp_s);
          if (f && f->kind == "silent") break;
          FrameJob job;
          job.stamp_s = e.stamp_s + shift_s;
          job.path = e.image_path;
          job.arrived = Clock::now();
          job.black = f && f->kind == "blackout";
          job.corrupt = f && f->kind == "corrupt";
          m.PushFrame(std::move(job));
          break;
        }
      }
    });
    if (swapped) {
      m.PushEvent(std::move(*swapped));
      swapped.reset();
    }
    replayed = stats.status();
  }
  const double cpu_replay_s = ThreadCpuSeconds() - cpu_start_s;
  inputs_done.store(true);
  if (camera_input.joinable()) camera_input.join();
  m.frames->Close();
  camera_thread.join();
  m.observed.Close();
  m.events.Close();
  estimator_thread.join();
  {
    std::lock_guard<std::mutex> lock(trim_mutex);
    trim_done = true;
  }
  trim_wake.notify_one();
  memory_thread.join();
  // The last pose and transform reach reliable subscribers before the exit.
  if (m.dds_outputs) m.dds_outputs->WaitForAcknowledgements(std::chrono::seconds(5));
  const double wall_s = std::chrono::duration<double>(Clock::now() - wall_start).count();

  // The state a restart resumes from, and the summary.
  SavedState state;
  {
    std::lock_guard<std::mutex> lock(m.status_mutex);
    state = {m.pose.stamp_s, m.pose.T_map_base, m.pose.covariance};
    m.cpu_replay_s = cpu_replay_s;
  }
  if (core::Status s = WriteServiceState(out / "state.json", state); !s.ok()) return s;
  if (m.localizer->options().mode == loc::LocalizerMode::kMapping ||
      m.localizer->options().smoother.upkeep.enabled) {
    if (core::Status s = loc::WriteAtlas(out / "atlas.json", m.localizer->CurrentAtlas()); !s.ok())
      return s;
  }
  nlohmann::ordered_json summary = StatusJsonOf(m);
  summary["wall_s"] = wall_s;
  summary["stopped"] = stop.load();
  if (resuming) {
    // Lines the previous run wrote after its saved state (killed before it
    // could save again), cut from the streamed outputs before appending.
    summary["resumed"] = {{"from_s", m.resume_after_s}, {"stale_lines_removed", stale_lines}};
  }
  if (core::Status s = core::WriteFileAtomically(out / "summary.json", summary.dump(2) + "\n");
      !s.ok())
    return s;
  if (!replayed.ok()) return replayed;
  return summary;
}

nlohmann::ordered_json Service::StatusJson() const { return StatusJsonOf(*impl_); }

nlohmann::ordered_json Service::StatusJsonOf(const Impl& m) {
  std::lock_guard<std::mutex> lock(m.status_mutex);
  nlohmann::ordered_json j;
  const loc::PoseEstimate& p = m.pose;
  j["stamp_s"] = p.stamp_s;
  j["pose"] = {{"x_m", p.T_map_base.x()},
               {"y_m", p.T_map_base.y()},
               {"yaw_deg", p.T_map_base.yaw() * 180.0 / std::numbers::pi}};
  j["cov"] = nlohmann::ordered_json::array();
  for (int i = 0; i < 9; ++i) j["cov"].push_back(p.covariance(i / 3, i % 3));
  j["mode"] = loc::ModeName(m.localizer->options());
  j["started"] = m.localizer->started();
  j["counters"] = loc::CountersJson(m.counters);
  if (m.self_calibration) {
    nlohmann::ordered_json s =
        loc::MountEstimateJson(m.self_calibration->estimate(), &m.self_calibration->applied(),
                               &m.self_calibration->observed());
    s["mount_updates"] = m.self_calibration->mount_updates();
    s["mount_rebuilds"] = m.mount_rebuilds.load();
    s["mount_rebuild_failures"] = m.mount_rebuild_failures.load();
    s["mount_estimate"] = m.mount_estimate_path.string();
    s["mount_estimate_restored"] = m.mount_estimate_restored;
    s["mount_estimate_write_failures"] = m.mount_estimate_write_failures.load();
    j["self_calibration"] = s;
  }
  // Per second of data time (the sensors' own rates, also in a replay faster
  // than real time); null until a second of data has passed.
  if (m.rate_samples.size() >= 2 &&
      m.rate_samples.back().stamp_s - m.rate_samples.front().stamp_s >= 1.0) {
    const Impl::RateSample& a = m.rate_samples.front();
    const Impl::RateSample& b = m.rate_samples.back();
    const double dt = b.stamp_s - a.stamp_s;
    j["rates_hz"] = {
        {"wheel_readings", static_cast<double>(b.wheel_readings - a.wheel_readings) / dt},
        {"frames", static_cast<double>(b.frames - a.frames) / dt},
        {"scans", static_cast<double>(b.scans - a.scans) / dt}};
  } else {
    j["rates_hz"] = nullptr;
  }
  j["camera_stage"] = {{"processed", m.camera_processed.load()},
                       {"skipped_not_due", m.camera_not_due.load()},
                       {"without_odometry", m.observations_without_odometry.load()},
                       {"dropped_queue_full", m.camera_dropped.load()},
                       {"unreadable", m.camera_unreadable.load()},
                       {"source_errors", m.camera_source_errors.load()},
                       {"source_opened", m.camera_reopens.load()}};
  j["odometry_poses_out"] = m.odometry_out;
  j["latency_ms"] = {{"n", m.latency_ms.size()},
                     {"median", Percentile(m.latency_ms, 0.5)},
                     {"p99", Percentile(m.latency_ms, 0.99)}};
  j["cpu_s"] = {
      {"replay", m.cpu_replay_s}, {"camera", m.cpu_camera_s}, {"estimator", m.cpu_estimator_s}};
  j["faults"] = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < m.config.faults.size() && i < m.fault_tracks.size(); ++i) {
    const InjectedFault& f = m.config.faults[i];
    const Impl::FaultTrack& t = m.fault_tracks[i];
    const char* sensor = f.sensor == InjectedFault::Sensor::kCamera  ? "camera"
                         : f.sensor == InjectedFault::Sensor::kLidar ? "lidar"
                         : f.sensor == InjectedFault::Sensor::kClock ? "clock"
                                                                     : "odometry";
    j["faults"].push_back(
        {{"sensor", sensor},
         {"kind", f.kind},
         {"from_s", f.from_s},
         {"to_s", f.to_s},
         {"from_stamp_s", m.replay_first_s + f.from_s},
         {"to_stamp_s", m.replay_first_s + f.to_s},
         {"degraded_reported", t.degraded_seen},
         {"recovered_after_s", t.recovered_at_s ? *t.recovered_at_s - f.to_s : -1.0}});
  }
  if (m.dds) j["dds"] = m.DdsJson();
  j["memory_trims"] = {
      {"n", m.memory_trims}, {"total_ms", m.trim_ms_total}, {"max_ms", m.trim_ms_max}};
  j["rss_mb"] = nlohmann::ordered_json::array();
  for (const auto& [data_s, mb] : m.rss_samples) j["rss_mb"].push_back({data_s, mb});
  j["last_keyframe"] = m.last_keyframe;
  return j;
}

}  // namespace groundline::service
