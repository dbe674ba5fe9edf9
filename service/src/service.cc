#include "groundline/service/service.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <fstream>
#include <limits>
#include <mutex>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <thread>
#include <unistd.h>

#include "groundline/core/atomic_file.h"
#include "groundline/core/dataset.h"
#include "groundline/core/dataset_streams.h"
#include "groundline/core/trajectory_io.h"
#include "groundline/io/frame_source.h"
#include "groundline/localization/localizer_json.h"
#include "groundline/service/dataset_localizer.h"
#include "groundline/service/replay.h"
#include "service_queues.h"
#include "status_page.h"

// Last: <resolv.h>, which it includes, defines the macro _res that Eigen uses as a name.
#include <httplib.h>

namespace groundline::service {
namespace {

namespace fs = std::filesystem;
namespace loc = localization;
using localization::KeyframeSelector;
using Clock = std::chrono::steady_clock;
using internal::BoundedQueue;

double ThreadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5))];
}

struct FrameJob {
  double stamp_s = 0.0;
  fs::path path;
  cv::Mat grey;  // a camera's decoded frame (else decoded from path)
  Clock::time_point arrived;
  // Injected faults (InjectedFault): a black frame, or one that does not decode.
  bool black = false;
  bool corrupt = false;
};

// Resident set size [MB] (/proc/self/statm).
double ResidentMb() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / 1048576.0;
}
struct Observed {
  loc::ConvertedObservations observations;
  Clock::time_point arrived;
};
struct EstimatorEvent {
  enum class Kind { kWheel, kScan } kind = Kind::kWheel;
  core::WheelEncoderReading wheel;
  core::LaserScan scan;
};

loc::LocalizerOptions PresetOptions(const std::string& preset) {
  if (preset == "fusion") return loc::LocalizerOptions::ForFusion();
  if (preset == "lines") {
    loc::LocalizerOptions o = loc::LocalizerOptions::ForFusion();
    o.use_lidar = false;
    return o;
  }
  loc::LocalizerOptions o;
  o.mode = preset == "lidar" ? loc::LocalizerMode::kLidar : loc::LocalizerMode::kOdometry;
  return o;
}

}  // namespace

struct Service::Impl {
  ServiceConfig config;
  core::Dataset dataset;
  std::unique_ptr<loc::Localizer> localizer;
  std::shared_ptr<const loc::FloorFrontEnd> camera;
  loc::Atlas atlas;
  std::optional<loc::PoseEstimate> start;
  double resume_after_s = -std::numeric_limits<double>::infinity();
  bool relocalize = false;

  std::unique_ptr<BoundedQueue<FrameJob>> frames;
  BoundedQueue<EstimatorEvent> events{4096};
  BoundedQueue<Observed> observed{64};
  // Stamps of the frames in the camera stage (queued or being processed).
  std::mutex pending_mutex;
  std::multiset<double> pending_frames;
  std::atomic<long> camera_dropped{0}, camera_unreadable{0}, camera_processed{0};
  std::atomic<long> camera_not_due{0};
  // The estimator's odometry since its last keyframe, for the camera stage:
  // a frame taken while the vehicle is far from the next keyframe is not
  // extracted (it would be skipped), which keeps a 30 fps camera cheap.
  std::atomic<double> since_keyframe_m{1e9}, since_keyframe_rad{1e9};
  std::atomic<double> since_stamp_s{0.0}, speed_mps{0.0}, yaw_rate_radps{0.0};
  double not_due_fraction = 0.8;

  // Shared with the HTTP thread.
  mutable std::mutex status_mutex;
  nlohmann::ordered_json last_keyframe;
  loc::PoseEstimate pose;
  loc::LocalizerCounters counters;
  std::vector<std::uint8_t> bev_png;
  std::string atlas_json;
  std::vector<double> latency_ms;
  // (data time since the first reading [s], RSS [MB]) every 600 s of data.
  std::vector<std::pair<double, double>> rss_samples;
  std::optional<double> first_reading_s;
  // Data time of the replay's first event, and per injected fault: whether a
  // keyframe reported the degradation, and when the mode was "full" again.
  double replay_first_s = 0.0;
  struct FaultTrack {
    bool degraded_seen = false;
    std::optional<double> recovered_at_s;
  };
  std::vector<FaultTrack> fault_tracks;
  double cpu_replay_s = 0.0, cpu_camera_s = 0.0, cpu_estimator_s = 0.0;
  long odometry_out = 0;

  // inputs.camera: frames from a FrameSource on their own thread.
  std::atomic<double> replay_now_s{-1e300};
  // The newest frame handed to the camera stage (stamp, wall time) and the
  // frame period seen: a reading at or past the next frame's expected time
  // waits (max_frame_wait_s) for it, unless the camera has stalled.
  std::atomic<double> frame_watermark_s{-1e300}, frame_period_s{0.0};
  std::atomic<Clock::rep> frame_wall_ticks{0};
  std::atomic<long> camera_source_errors{0}, camera_reopens{0};
  void CameraInput(const std::atomic<bool>& done);
  void PushFrame(FrameJob job);

  httplib::Server http;
  int port = 0;
  std::thread http_thread;

  void CameraStage();
  void EstimatorStage(std::ofstream& keyframes, std::ofstream& odometry, std::ofstream& health);
  void ReleasePending(double stamp_s) {
    std::lock_guard<std::mutex> lock(pending_mutex);
    if (auto it = pending_frames.find(stamp_s); it != pending_frames.end()) pending_frames.erase(it);
  }
  bool FramePendingAtOrBefore(double stamp_s) {
    std::lock_guard<std::mutex> lock(pending_mutex);
    return !pending_frames.empty() && *pending_frames.begin() <= stamp_s + 1e-9;
  }
};

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
  impl->frames = std::make_unique<BoundedQueue<FrameJob>>(
      static_cast<std::size_t>(config.camera_queue_depth));
  core::DatasetReadOptions read;
  read.check_image_files = false;
  read.load_scans = false;
  core::Result<core::Dataset> dataset = core::ReadDataset(config.replay_dataset, read);
  if (!dataset.ok()) return dataset.status();
  impl->dataset = std::move(dataset).value();
  DatasetLocalizerOptions options;
  options.localizer = PresetOptions(config.preset);
  options.atlas_path = config.atlas;
  core::Result<DatasetSetup> setup = SetupFromDataset(config.replay_dataset, impl->dataset, options);
  if (!setup.ok()) return setup.status();
  impl->camera = setup->setup.camera;
  impl->atlas = setup->setup.atlas;
  core::Result<std::unique_ptr<loc::Localizer>> localizer =
      loc::Localizer::Create(options.localizer, std::move(setup->setup));
  if (!localizer.ok()) return localizer.status();
  impl->localizer = std::move(localizer).value();

  // The start: a saved state (resume), the configured pose, relocalization,
  // or the dataset's start pose.
  const fs::path state_path = fs::path(config.output_dir) / "state.json";
  core::Status started = core::Status::Ok();
  if (config.resume && fs::exists(state_path)) {
    std::ifstream in(state_path);
    const nlohmann::json state = nlohmann::json::parse(in, nullptr, false);
    if (state.is_discarded() || !state.contains("stamp_s") || !state.contains("cov") ||
        state["cov"].size() != 9) {
      return core::Status::Error(state_path.string() +
                                 ": expected the service's saved state (stamp_s, x_m, y_m, "
                                 "yaw_rad, cov[9]); delete it or set start.resume: false");
    }
    core::Matrix3 cov;
    for (int i = 0; i < 9; ++i) cov(i / 3, i % 3) = state["cov"][i].get<double>();
    impl->resume_after_s = state["stamp_s"].get<double>();
    started = impl->localizer->SetInitialPose(
        impl->resume_after_s,
        core::SE2(state["x_m"].get<double>(), state["y_m"].get<double>(), state["yaw_rad"].get<double>()),
        cov);
    if (!started.ok()) return started.WithContext(state_path.string());
  } else if (config.initial_pose) {
    const auto& p = *config.initial_pose;
    started = impl->localizer->SetInitialPose(setup->first_reading_s,
                                              core::SE2(p[0], p[1], p[2] * std::numbers::pi / 180.0),
                                              StartCovariance(core::StartPose{}));
  } else if (config.relocalize) {
    started = impl->localizer->RequestRelocalization();
  } else if (setup->start_pose) {
    started = impl->localizer->SetInitialPose(
        std::min(setup->first_reading_s, setup->start_pose->stamp_s),
        setup->start_pose->T_map_base, StartCovariance(*setup->start_pose));
  } else {
    return core::Status::Error(config.replay_dataset +
                               ": no start: the manifest has no start_pose; set "
                               "start.initial_pose or start.relocalize");
  }
  if (!started.ok()) return started;
  impl->pose = impl->localizer->Current();
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
    m->port = config.http_port == 0 ? m->http.bind_to_any_port(config.http_address)
                                    : (m->http.bind_to_port(config.http_address, config.http_port)
                                           ? config.http_port
                                           : -1);
    if (m->port < 0) {
      return core::Status::Error("http: cannot listen on " + config.http_address + ":" +
                                 std::to_string(config.http_port) +
                                 " (in use? set http.port, or 0 for any free port)");
    }
    m->http_thread = std::thread([m] { m->http.listen_after_bind(); });
  }
  return std::unique_ptr<Service>(new Service(std::move(impl)));
}

void Service::Impl::PushFrame(FrameJob job) {
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
      core::Result<std::unique_ptr<io::FrameSource>> opened = io::OpenFrameSource(config.camera_uri);
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
  while (!frames->closed_and_empty()) {
    std::optional<FrameJob> job = frames->Pop(std::chrono::milliseconds(20));
    if (!job) continue;
    // The motion since the last keyframe extrapolated to the frame's time.
    const KeyframeSelector::Options& due = localizer->options().keyframes;
    const double ahead_s = std::max(0.0, job->stamp_s - since_stamp_s.load());
    if (since_keyframe_m.load() + speed_mps.load() * ahead_s <
            not_due_fraction * due.min_translation_m &&
        since_keyframe_rad.load() + yaw_rate_radps.load() * ahead_s <
            not_due_fraction * due.min_rotation_rad) {
      ++camera_not_due;
      ReleasePending(job->stamp_s);
      continue;
    }
    cv::Mat grey;
    if (job->black && camera) {
      grey = cv::Mat::zeros(camera->image_height_px(), camera->image_width_px(), CV_8UC1);
    } else if (!job->grey.empty()) {
      grey = job->grey;
    } else if (!job->corrupt) {
      grey = cv::imread(job->path.string(), cv::IMREAD_GRAYSCALE);
    }
    // A camera delivers decoded frames: the latency counts from here.
    job->arrived = Clock::now();
    cv::Mat bev;
    core::Result<loc::ConvertedObservations> seen =
        grey.empty() || !camera ? core::Status::Error("unreadable frame " + job->path.string())
                                : camera->Observe(grey, job->stamp_s, &bev);
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
      observed.PushWait(Observed{std::move(seen).value(), job->arrived});
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
  std::deque<std::pair<core::WheelEncoderReading, Clock::time_point>> held;
  std::optional<Clock::time_point> last_frame_arrival;
  // As fast as possible there is no deadline: a reading waits for its frame.
  const auto wait = config.replay_speed == 0.0
                        ? Clock::duration::max()
                        : std::chrono::duration_cast<Clock::duration>(
                              std::chrono::duration<double>(config.max_frame_wait_s));
  const loc::LocalizerMode mode = localizer->options().mode;
  auto apply = [&](const core::WheelEncoderReading& r) {
    const double before_s = localizer->started() ? localizer->Current().stamp_s : -1.0;
    std::optional<loc::KeyframeOutput> k = localizer->AddWheelReading(r);
    std::lock_guard<std::mutex> lock(status_mutex);
    if (!first_reading_s) first_reading_s = r.stamp_s;
    const double data_s = r.stamp_s - *first_reading_s;
    if (rss_samples.empty() || data_s >= rss_samples.back().first + 600.0) {
      rss_samples.emplace_back(data_s, ResidentMb());
    }
    if (localizer->started() && localizer->Current().stamp_s != before_s) {
      pose = localizer->Current();
      odometry << core::FormatTumLine({pose.stamp_s, pose.T_map_base, std::nullopt});
      ++odometry_out;
    }
    if (k) {
      nlohmann::ordered_json line = loc::KeyframeJson(*k, mode);
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
  const auto frame_expected = [&](double stamp_s) {
    const double period = frame_period_s.load();
    if (period <= 0.0) return false;
    const Clock::duration since_frame =
        Clock::now() - Clock::time_point(Clock::duration(frame_wall_ticks.load()));
    const bool stalled = since_frame > std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(std::max(0.2, 3.0 * period)));
    return !stalled && stamp_s + 1e-9 >= frame_watermark_s.load() + 0.9 * period;
  };
  while (!events.closed_and_empty() || !observed.closed_and_empty() || !held.empty()) {
    while (std::optional<Observed> o = observed.Pop(std::chrono::milliseconds(0))) {
      const double stamp_s = o->observations.observations.stamp_s;
      taken.push_back(std::move(*o));
      ReleasePending(stamp_s);
    }
    std::optional<EstimatorEvent> event = events.Pop(std::chrono::milliseconds(2));
    if (event) {
      switch (event->kind) {
        case EstimatorEvent::Kind::kWheel:
          held.emplace_back(event->wheel, Clock::now());
          break;
        case EstimatorEvent::Kind::kScan:
          localizer->AddScan(std::move(event->scan));
          break;
      }
    }
    // Apply the held readings whose frames are in (or that waited long
    // enough), each after the observations of its time.
    const bool closing = events.closed_and_empty();
    while (!held.empty()) {
      const auto& [reading, since] = held.front();
      const bool waiting = FramePendingAtOrBefore(reading.stamp_s) ||
                           (!closing && frame_expected(reading.stamp_s));
      if (waiting && Clock::now() - since < wait) break;
      while (!taken.empty() && taken.front().observations.observations.stamp_s <= reading.stamp_s + 1e-9) {
        last_frame_arrival = taken.front().arrived;
        localizer->AddFloorObservations(std::move(taken.front().observations));
        taken.pop_front();
      }
      apply(reading);
      held.pop_front();
    }
  }
  std::lock_guard<std::mutex> lock(status_mutex);
  cpu_estimator_s = ThreadCpuSeconds() - cpu_start_s;
}

core::Result<nlohmann::ordered_json> Service::Run(const std::atomic<bool>& stop) {
  Impl& m = *impl_;
  const fs::path out(m.config.output_dir);
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) return core::Status::Error(out.string() + ": cannot create the output directory: " + ec.message());
  const auto mode = std::ios::out | (std::isfinite(m.resume_after_s) ? std::ios::app : std::ios::trunc);
  std::ofstream keyframes(out / "trajectory.tum", mode), odometry(out / "trajectory_odometry_rate.tum", mode),
      health(out / "health.jsonl", mode);
  if (!keyframes || !odometry || !health) {
    return core::Status::Error(out.string() + ": cannot write the run outputs");
  }
  const Clock::time_point wall_start = Clock::now();
  const double first_s = std::min(m.dataset.wheel_encoders.front().stamp_s,
                                  m.dataset.images.empty() ? 1e300 : m.dataset.images.front().stamp_s);
  // One pass lasts from the first event to one reading period after the last.
  const double period_s = m.dataset.wheel_encoders.back().stamp_s - first_s +
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

  core::Status replayed = core::Status::Ok();
  const double cpu_start_s = ThreadCpuSeconds();
  const auto faulty = [&m, first_s](InjectedFault::Sensor sensor, double stamp_s) -> const InjectedFault* {
    for (const InjectedFault& f : m.config.faults) {
      if (f.sensor == sensor && stamp_s - first_s >= f.from_s && stamp_s - first_s < f.to_s) return &f;
    }
    return nullptr;
  };
  for (int pass = 0; pass < m.config.replay_loops && replayed.ok() && !stop.load(); ++pass) {
    core::Result<core::DatasetStreams> streams =
        core::DatasetStreams::Open(m.config.replay_dataset, m.dataset);
    if (!streams.ok()) {
      replayed = streams.status();
      break;
    }
    const double shift_s = pass * period_s;
    ReplayOptions options;
    options.speed = m.config.replay_speed;
    options.start_after_s = m.resume_after_s - shift_s;
    options.stop = [&stop] { return stop.load(); };
    core::Result<ReplayStats> stats = ReplayEvents(*streams, options, [&](core::DatasetEvent& e) {
      m.replay_now_s.store(e.stamp_s + shift_s);
      if (e.kind == core::DatasetEvent::Kind::kFrame && !m.config.camera_uri.empty()) return;
      switch (e.kind) {
        case core::DatasetEvent::Kind::kWheel: {
          EstimatorEvent event;
          event.wheel = e.wheel;
          event.wheel.stamp_s += shift_s;
          if (const InjectedFault* f = faulty(InjectedFault::Sensor::kOdometry, e.stamp_s)) {
            const double value = f->kind == "nan" ? std::numeric_limits<double>::quiet_NaN() : 0.0;
            event.wheel.left_delta_rad = event.wheel.right_delta_rad = value;
          }
          m.events.PushWait(std::move(event));
          break;
        }
        case core::DatasetEvent::Kind::kScan: {
          if (faulty(InjectedFault::Sensor::kLidar, e.stamp_s)) break;
          EstimatorEvent event;
          event.kind = EstimatorEvent::Kind::kScan;
          event.scan = std::move(e.scan);
          event.scan.stamp_s += shift_s;
          m.events.PushWait(std::move(event));
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
  const double wall_s = std::chrono::duration<double>(Clock::now() - wall_start).count();

  // The state a restart resumes from, and the summary.
  nlohmann::ordered_json state;
  {
    std::lock_guard<std::mutex> lock(m.status_mutex);
    const loc::PoseEstimate& p = m.pose;
    state = {{"stamp_s", p.stamp_s}, {"x_m", p.T_map_base.x()}, {"y_m", p.T_map_base.y()},
             {"yaw_rad", p.T_map_base.yaw()}, {"cov", nlohmann::ordered_json::array()}};
    for (int i = 0; i < 9; ++i) state["cov"].push_back(p.covariance(i / 3, i % 3));
    m.cpu_replay_s = cpu_replay_s;
  }
  if (core::Status s = core::WriteFileAtomically(out / "state.json", state.dump(2) + "\n"); !s.ok()) return s;
  if (m.localizer->options().mode == loc::LocalizerMode::kMapping) {
    if (core::Status s = loc::WriteAtlas(out / "atlas.json", m.localizer->CurrentAtlas()); !s.ok()) return s;
  }
  nlohmann::ordered_json summary = StatusJsonOf(m);
  summary["wall_s"] = wall_s;
  summary["stopped"] = stop.load();
  if (core::Status s = core::WriteFileAtomically(out / "summary.json", summary.dump(2) + "\n"); !s.ok()) return s;
  if (!replayed.ok()) return replayed;
  return summary;
}

nlohmann::ordered_json Service::StatusJson() const { return StatusJsonOf(*impl_); }

nlohmann::ordered_json Service::StatusJsonOf(const Impl& m) {
  std::lock_guard<std::mutex> lock(m.status_mutex);
  nlohmann::ordered_json j;
  const loc::PoseEstimate& p = m.pose;
  j["stamp_s"] = p.stamp_s;
  j["pose"] = {{"x_m", p.T_map_base.x()}, {"y_m", p.T_map_base.y()},
               {"yaw_deg", p.T_map_base.yaw() * 180.0 / std::numbers::pi}};
  j["cov"] = nlohmann::ordered_json::array();
  for (int i = 0; i < 9; ++i) j["cov"].push_back(p.covariance(i / 3, i % 3));
  j["mode"] = loc::ModeName(m.localizer->options());
  j["started"] = m.localizer->started();
  j["counters"] = loc::CountersJson(m.counters);
  j["camera_stage"] = {{"processed", m.camera_processed.load()},
                       {"skipped_not_due", m.camera_not_due.load()},
                       {"dropped_queue_full", m.camera_dropped.load()},
                       {"unreadable", m.camera_unreadable.load()},
                       {"source_errors", m.camera_source_errors.load()},
                       {"source_opened", m.camera_reopens.load()}};
  j["odometry_poses_out"] = m.odometry_out;
  j["latency_ms"] = {{"n", m.latency_ms.size()},
                     {"median", Percentile(m.latency_ms, 0.5)},
                     {"p99", Percentile(m.latency_ms, 0.99)}};
  j["cpu_s"] = {{"replay", m.cpu_replay_s}, {"camera", m.cpu_camera_s}, {"estimator", m.cpu_estimator_s}};
  j["faults"] = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < m.config.faults.size() && i < m.fault_tracks.size(); ++i) {
    const InjectedFault& f = m.config.faults[i];
    const Impl::FaultTrack& t = m.fault_tracks[i];
    const char* sensor = f.sensor == InjectedFault::Sensor::kCamera  ? "camera"
                         : f.sensor == InjectedFault::Sensor::kLidar ? "lidar"
                                                                     : "odometry";
    j["faults"].push_back({{"sensor", sensor},
                           {"kind", f.kind},
                           {"from_s", f.from_s},
                           {"to_s", f.to_s},
                           {"from_stamp_s", m.replay_first_s + f.from_s},
                           {"to_stamp_s", m.replay_first_s + f.to_s},
                           {"degraded_reported", t.degraded_seen},
                           {"recovered_after_s", t.recovered_at_s ? *t.recovered_at_s - f.to_s : -1.0}});
  }
  j["rss_mb"] = nlohmann::ordered_json::array();
  for (const auto& [data_s, mb] : m.rss_samples) j["rss_mb"].push_back({data_s, mb});
  j["last_keyframe"] = m.last_keyframe;
  return j;
}

}  // namespace groundline::service
