// `groundline calibrate history RUN`: a recorded run's self-calibration of
// the camera mount (calibration/self_calibration_history.h).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "groundline/calibration/self_calibration_history.h"
#include "groundline/core/atomic_file.h"
#include "groundline/core/dataset_records.h"

namespace groundline::tools {
namespace {

constexpr char kHistoryHelp[] =
    R"(Reports the camera mount's self-calibration over a recorded run: the run
directory of `groundline localize --self-calibrate` (its health.jsonl has the
estimate at every keyframe). Prints the first and last estimate, the steps
detected and when the alarm was raised and cleared, and writes
RUN/self_calibration.html: pitch, roll, height and yaw over time, each with
its 3-sigma band, the commissioned mount and red marks where the alarm was
raised.

With --truth (a simulated run's ground_truth_extrinsics.csv: evaluation only,
a vehicle has no such file) the page also draws the true mount, and the
errors of the estimate against it are printed and written to
RUN/self_calibration.json: maximum, RMS and the share of keyframes whose
truth lies within 3 sigma, per component, from --from seconds on.

Exit code: 0 when it ran (an alarm is reported, not an error), 1 unreadable
input, 2 usage error.

Example:
  groundline localize --dataset b_knock --mode lines --lidar --self-calibrate --out run
  groundline calibrate history run --truth b_knock/ground_truth_extrinsics.csv)";

constexpr char kHistoryCommand[] = "groundline calibrate history";

struct HistoryFlags {
  std::string run_dir;
  std::string truth;
  double from_s = -1e300;
};

const auto Shown = calibration::MountComponentInUnit;
const auto Unit = calibration::MountComponentUnit;
const auto Name = calibration::MountComponentName;

int Fail(const std::string& message) {
  std::fprintf(stderr, "%s: %s\n", kHistoryCommand, message.c_str());
  return 1;
}

int RunHistory(const HistoryFlags& flags) {
  const std::filesystem::path run(flags.run_dir);
  core::Result<std::vector<calibration::SelfCalibrationSample>> history =
      calibration::ReadSelfCalibrationHistory(run / "health.jsonl");
  if (!history.ok()) return Fail(history.message());
  std::optional<std::vector<core::CameraExtrinsicsRecord>> truth;
  if (!flags.truth.empty()) {
    core::Result<std::vector<core::CameraExtrinsicsRecord>> t =
        core::ReadGroundTruthExtrinsics(flags.truth);
    if (!t.ok()) return Fail(t.message());
    if (t->empty()) return Fail(flags.truth + ": no records");
    truth = std::move(t).value();
  }
  const calibration::SelfCalibrationSample& first = history->front();
  const calibration::SelfCalibrationSample& last = history->back();
  std::printf("%zu keyframes, %.1f-%.1f s; %d windows fused, %d steps detected\n",
              history->size(), first.stamp_s, last.stamp_s, last.windows, last.steps);
  for (const auto* s : {&first, &last}) {
    std::printf("  %s (%.1f s):", s == &first ? "first" : "last ", s->stamp_s);
    for (int i = 0; i < 4; ++i) {
      std::printf(" %s %.3f +- %.3f %s%s", Name(i), Shown(i, s->value(i)),
                  Shown(i, s->sigma(i)), Unit(i), i < 3 ? "," : "\n");
    }
  }
  // Each time the alarm is raised (its figures change from keyframe to
  // keyframe while it stands; the page lists every distinct message).
  int alarms = 0;
  bool raised = false;
  for (const calibration::SelfCalibrationSample& s : *history) {
    if (s.alarm && !raised) {
      std::printf("  alarm raised at %.1f s: %s\n", s.stamp_s, s.alarm_message.c_str());
    } else if (!s.alarm && raised) {
      std::printf("  alarm cleared at %.1f s\n", s.stamp_s);
    }
    raised = s.alarm;
    alarms += s.alarm ? 1 : 0;
  }
  if (alarms == 0) std::printf("  no alarm\n");
  if (raised) std::printf("  alarm standing at the end: %s\n", last.alarm_message.c_str());

  nlohmann::ordered_json j;
  j["run"] = flags.run_dir;
  j["keyframes"] = history->size();
  j["windows"] = last.windows;
  j["steps"] = last.steps;
  j["alarm_keyframes"] = alarms;
  if (truth) {
    const calibration::SelfCalibrationErrors e =
        calibration::CompareWithTruth(*history, *truth, flags.from_s);
    std::printf("  against the truth (evaluation only; %d keyframes with an estimate%s):\n",
                e.samples, flags.from_s > -1e299 ? ", from --from on" : "");
    nlohmann::ordered_json errors;
    errors["truth"] = flags.truth;
    errors["keyframes"] = e.samples;
    for (int i = 0; i < 4; ++i) {
      std::printf("    %-6s max %.3f %s, rms %.3f %s, within 3 sigma %.1f %%\n", Name(i),
                  Shown(i, e.max_abs(i)), Unit(i), Shown(i, e.rms(i)), Unit(i),
                  100.0 * e.within_3_sigma(i));
      errors[std::string(Name(i)) + "_max_" + Unit(i)] = Shown(i, e.max_abs(i));
      errors[std::string(Name(i)) + "_rms_" + Unit(i)] = Shown(i, e.rms(i));
      errors[std::string(Name(i)) + "_within_3_sigma"] = e.within_3_sigma(i);
    }
    j["errors_against_truth"] = errors;
  }
  const std::string html = calibration::SelfCalibrationHistoryHtml(
      *history, truth ? &*truth : nullptr, "Camera mount self-calibration: " + flags.run_dir);
  for (const core::Status& s :
       {core::WriteFileAtomically(run / "self_calibration.html", html),
        core::WriteFileAtomically(run / "self_calibration.json", j.dump(1) + "\n")}) {
    if (!s.ok()) return Fail(s.message());
  }
  std::printf("  wrote %s and %s\n", (run / "self_calibration.html").c_str(),
              (run / "self_calibration.json").c_str());
  return 0;
}

}  // namespace

void AddCalibrateHistorySubcommand(CLI::App* calibrate, CommandRunner* run) {
  auto flags = std::make_shared<HistoryFlags>();
  CLI::App* cmd = calibrate->add_subcommand(
      "history", "A recorded run's self-calibration of the camera mount, with a plot");
  cmd->footer(kHistoryHelp);
  cmd->add_option("RUN", flags->run_dir, "Run directory of localize --self-calibrate")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--truth", flags->truth,
                  "A simulated run's ground_truth_extrinsics.csv (evaluation only)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--from", flags->from_s,
                  "With --truth: the errors from this stamp on, seconds (default: from the "
                  "first window)");
  cmd->callback([flags, run] { *run = [flags] { return RunHistory(*flags); }; });
}

}  // namespace groundline::tools
