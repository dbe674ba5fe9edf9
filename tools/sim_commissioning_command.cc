// `groundline sim-commissioning`: a simulated floor-commissioning session.
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "groundline/core/atomic_file.h"
#include "groundline/sim/commissioning_scene.h"

namespace groundline::tools {
namespace {

struct SimCommissioningFlags {
  std::string out;
  std::uint64_t seed = 1;
  int poses = 6;
  bool small = false;
};

constexpr char kSimCommissioningHelp[] =
    R"(Simulates floor commissioning: the vehicle creeps (0.05 m/s) across a mat of
tag36h11 AprilTags lying on the floor (default 6 x 5 tags of 0.16 m, 0.36 m apart,
surveyed yaws drawn by the seed) and its floor camera (1280x1024, 6 mm lens, mild
OpenCV distortion) takes one image at each of --poses stops, rendered through
the camera model with anti-aliasing, concrete texture, a light gradient, motion
blur and sensor noise. The true mount is the reference mount perturbed by a few
millimetres and tenths of a degree.

Writes into --out: images/pose_NNN.png, tag_layout.yaml (frame: floor, with the
vehicle's surveyed pose of each image), camera.cameramodel (the intrinsics) and
true_extrinsics.yaml (the mount to recover).

Example:
  groundline sim-commissioning --out scene
  groundline calibrate floor --images scene/images --layout scene/tag_layout.yaml \
      --camera scene/camera.cameramodel --out scene/calibration)";

int RunSimCommissioning(const SimCommissioningFlags& flags) {
  sim::CommissioningOptions options =
      flags.small ? sim::CommissioningOptions::Small() : sim::CommissioningOptions();
  options.seed = flags.seed;
  options.render.seed = flags.seed;
  options.poses = flags.poses;
  core::Result<sim::CommissioningScene> scene = sim::MakeCommissioningScene(options);
  if (!scene.ok()) {
    std::fprintf(stderr, "groundline sim-commissioning: %s\n", scene.message().c_str());
    return 2;
  }
  core::Result<std::vector<sim::GreyImage>> images =
      sim::RenderCommissioningImages(*scene, options);
  // Written into a staging folder moved into --out at the end: a failed run
  // leaves --out as it was.
  core::Result<core::StagedDirectory> staged = core::StagedDirectory::Create(flags.out);
  if (!staged.ok()) {
    std::fprintf(stderr, "groundline sim-commissioning: %s\n", staged.message().c_str());
    return 1;
  }
  core::Status written =
      images.ok() ? sim::WriteCommissioningScene(*scene, *images, staged->path()) : images.status();
  if (written.ok()) written = staged->Commit();
  if (!written.ok()) {
    std::fprintf(stderr, "groundline sim-commissioning: %s\n", written.message().c_str());
    return 1;
  }
  std::printf("%s: %zu images of %zu tags, camera %dx%d\n", flags.out.c_str(), images->size(),
              scene->layout.tags.size(), scene->camera.width_px(), scene->camera.height_px());
  return 0;
}

}  // namespace

CLI::App* AddSimCommissioningCommand(CLI::App& parent, CommandRunner* run) {
  auto flags = std::make_shared<SimCommissioningFlags>();
  CLI::App* cmd = parent.add_subcommand(
      "sim-commissioning", "Simulate floor commissioning: a tag mat seen by the floor camera");
  cmd->footer(kSimCommissioningHelp);
  cmd->add_option("-o,--out", flags->out, "Output directory")->required();
  cmd->add_option("--seed", flags->seed, "Seed of the tag yaws, vehicle poses and noise")
      ->capture_default_str();
  cmd->add_option("--poses", flags->poses, "Number of vehicle stops (images)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  cmd->add_flag("--small", flags->small,
                "480x384 camera looking more steeply down at larger tags (the unit-test scene)");
  cmd->callback([flags, run] { *run = [flags] { return RunSimCommissioning(*flags); }; });
  return cmd;
}

}  // namespace groundline::tools
