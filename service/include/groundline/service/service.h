// `groundline serve`: the localizer (localization/localizer.h) as a
// long-running process. Stages on their own threads with bounded queues:
//   input    the dataset replayed at its timestamps (real time or N x);
//   camera   frame -> BEV -> lines (FloorFrontEnd); its queue holds
//            queues.camera frames and drops the oldest when full (counted),
//            so a slow camera never blocks the odometry;
//   estimator  the Localizer; a wheel reading waits (at most
//            max_frame_wait_s) for a frame of its time still in the camera
//            stage, so the keyframe sits at the frame's time;
//   http     127.0.0.1 by default: /health.json, / (the status page),
//            /bev.png, /atlas.json.
// Outputs in output.dir: trajectory.tum (keyframes), trajectory_odometry_rate.tum,
// health.jsonl (streamed, one line per keyframe), summary.json and state.json
// (atomic, at the end). A stop request (SIGINT/SIGTERM in the CLI) ends the
// run cleanly; with start.resume a restart continues from state.json.
#ifndef GROUNDLINE_SERVICE_SERVICE_H_
#define GROUNDLINE_SERVICE_SERVICE_H_

#include <atomic>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "groundline/core/status.h"
#include "groundline/service/service_config.h"

namespace groundline::service {

class Service {
 public:
  // Errors: an unreadable dataset, calibration or atlas; a port in use.
  static core::Result<std::unique_ptr<Service>> Create(const ServiceConfig& config);
  ~Service();

  // Runs until the replay ends or `stop` is set; returns the summary
  // (also written to output.dir/summary.json).
  core::Result<nlohmann::ordered_json> Run(const std::atomic<bool>& stop);
  // The HTTP port actually bound (0 when http is off).
  int http_port() const;
  // The /health.json document (thread-safe).
  nlohmann::ordered_json StatusJson() const;

 private:
  struct Impl;
  explicit Service(std::unique_ptr<Impl> impl);
  static nlohmann::ordered_json StatusJsonOf(const Impl& impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace groundline::service

#endif  // GROUNDLINE_SERVICE_SERVICE_H_
