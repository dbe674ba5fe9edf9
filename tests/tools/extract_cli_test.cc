// `groundline extract` end to end through the executable: a folder of small
// pinhole camera images of a floor with one tape line, plus one corrupt PNG
// that must be reported by name and skipped.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <opencv2/imgcodecs.hpp>

#include "cli_runner.h"
#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/calibration/camera_model.h"
#include "groundline/calibration/camera_mount_yaml.h"
#include "groundline/calibration/floor_projection.h"
#include "groundline/calibration/mrcal_cameramodel_io.h"
#include "test_data.h"

namespace groundline {
namespace {

using testing::Quoted;
using testing::RunGroundline;

TEST(ExtractCli, FolderWithACorruptImage) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("extract_cli");
  const std::filesystem::path images = dir / "images";
  std::filesystem::create_directories(images);
  // A quarter-scale reference camera (same field of view), pinhole.
  const calibration::CameraModel camera = *calibration::CameraModel::Create(
      "LENSMODEL_PINHOLE", {283.0, 283.0, 159.5, 127.5}, 320, 256);
  const calibration::CameraMount mount;
  ASSERT_TRUE(calibration::WriteMrcalCameraModel(dir / "camera.cameramodel", camera).ok());
  ASSERT_TRUE(calibration::WriteCameraMountYaml(mount, dir / "extrinsics.yaml").ok());
  const calibration::FloorProjection projection(camera, mount);
  for (int k = 0; k < 3; ++k) {
    const double tape_y_m = 0.30 + 0.01 * k;  // 7.5 cm tape along x
    cv::Mat image(256, 320, CV_8U);
    for (int v = 0; v < 256; ++v) {
      for (int u = 0; u < 320; ++u) {
        double sum = 0.0;
        for (int s = 0; s < 4; ++s) {
          core::Result<Eigen::Vector2d> p =
              projection.FloorPointOfPixel({u - 0.375 + 0.25 * s, v - 0.375 + 0.25 * (3 - s)});
          sum += (p.ok() && std::abs(p->y() - tape_y_m) <= 0.0375) ? 190.0 : 70.0;
        }
        image.at<std::uint8_t>(v, u) = static_cast<std::uint8_t>(sum / 4.0);
      }
    }
    ASSERT_TRUE(cv::imwrite((images / ("frame" + std::to_string(k) + ".png")).string(), image));
  }
  std::ofstream(images / "frame9_corrupt.png") << "\x89PNG\r\n\x1a\nnot really a png";

  std::string out;
  const std::filesystem::path result = dir / "out";
  ASSERT_EQ(
      RunGroundline("extract " + Quoted(images) + " --camera " +
                        Quoted(dir / "camera.cameramodel") + " --extrinsics " +
                        Quoted(dir / "extrinsics.yaml") + " --png-every 1 --out " + Quoted(result),
                    dir, &out),
      0)
      << out;
  EXPECT_NE(out.find("frame9_corrupt.png"), std::string::npos) << out;
  std::ifstream jsonl(result / "lines.jsonl");
  std::string line;
  int frames = 0;
  while (std::getline(jsonl, line)) {
    const nlohmann::json frame = nlohmann::json::parse(line);
    ASSERT_EQ(frame["lines"].size(), 1u) << line;
    const nlohmann::json& l = frame["lines"][0];
    EXPECT_NEAR(l["rho_m"].get<double>(), 0.30 + 0.01 * frames, 0.004) << line;
    EXPECT_NEAR(l["alpha_rad"].get<double>(), std::numbers::pi / 2, 0.005) << line;
    EXPECT_EQ(l["kind"], "tape_longitudinal");
    EXPECT_EQ(l["cov"].size(), 4u);
    EXPECT_TRUE(frame.contains("ms"));
    EXPECT_TRUE(frame.contains("junctions"));
    ++frames;
  }
  EXPECT_EQ(frames, 3);
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(result / "summary.json"));
  EXPECT_EQ(summary["frames"], 3);
  ASSERT_EQ(summary["skipped"].size(), 1u);
  EXPECT_TRUE(summary["ms_per_frame_median"].is_number());
  EXPECT_FALSE(summary.contains("tpr"));  // no ground truth
  // The images are named after their source images; the overlay carries its
  // legend below the BEV (3x upsampled): a white strip of one row per colour.
  ASSERT_TRUE(std::filesystem::exists(result / "overlay_frame0.png"));
  ASSERT_TRUE(std::filesystem::exists(result / "bev_frame0.png"));
  const cv::Mat bev = cv::imread((result / "bev_frame0.png").string());
  const cv::Mat overlay = cv::imread((result / "overlay_frame0.png").string());
  ASSERT_FALSE(bev.empty());
  ASSERT_FALSE(overlay.empty());
  EXPECT_EQ(overlay.cols, 3 * bev.cols);
  EXPECT_EQ(overlay.rows, 3 * bev.rows + 5 * 18 + 6);  // 5 rows without ground truth
  const cv::Vec3b corner = overlay.at<cv::Vec3b>(overlay.rows - 1, overlay.cols - 1);
  EXPECT_EQ(corner, cv::Vec3b(255, 255, 255));
  // The legend's first swatch is the bright-line green.
  const cv::Vec3b swatch = overlay.at<cv::Vec3b>(3 * bev.rows + 3 + 9, 20);
  EXPECT_EQ(swatch, cv::Vec3b(0, 220, 0));

  // No image readable: exit 1 and no output folder at all.
  const std::filesystem::path none = dir / "none";
  std::filesystem::create_directories(none);
  std::ofstream(none / "bad.png") << "not a png";
  EXPECT_EQ(
      RunGroundline("extract " + Quoted(none) + " --out " + Quoted(dir / "none_out"), dir, &out), 1)
      << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "none_out"));
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    EXPECT_EQ(e.path().filename().string().find(".none_out.tmp"), std::string::npos);
  }

  // The calibration's floor: a mount known to 0.5 deg of pitch and 5 mm of
  // height bounds each line's covariance from below (a tape 1-2 m ahead
  // cannot be placed better than centimetres).
  const std::string map_command = "calibrate bev-uncertainty --camera " +
                                  Quoted(dir / "camera.cameramodel") + " --extrinsics " +
                                  Quoted(dir / "extrinsics.yaml");
  ASSERT_EQ(RunGroundline(map_command + " --sigma-pitch-deg 0.5 --sigma-height-mm 5 --out " +
                              Quoted(dir / "bev_uncertainty.json"),
                          dir, &out),
            0)
      << out;
  EXPECT_NE(out.find("worst"), std::string::npos) << out;
  const std::filesystem::path floored = dir / "out_floored";
  ASSERT_EQ(
      RunGroundline(
          "extract " + Quoted(images) + " --camera " + Quoted(dir / "camera.cameramodel") +
              " --extrinsics " + Quoted(dir / "extrinsics.yaml") + " --bev-uncertainty " +
              Quoted(dir / "bev_uncertainty.json") + " --png-every 0 --out " + Quoted(floored),
          dir, &out),
      0)
      << out;
  {
    std::ifstream plain_lines(result / "lines.jsonl"), floored_lines(floored / "lines.jsonl");
    std::string a, b;
    int compared = 0;
    while (std::getline(plain_lines, a) && std::getline(floored_lines, b)) {
      const nlohmann::json fa = nlohmann::json::parse(a), fb = nlohmann::json::parse(b);
      ASSERT_EQ(fa["lines"].size(), 1u);
      ASSERT_EQ(fb["lines"].size(), 1u);
      const double var_a = fa["lines"][0]["cov"][0].get<double>();
      const double var_b = fb["lines"][0]["cov"][0].get<double>();
      EXPECT_EQ(fa["lines"][0]["rho_m"], fb["lines"][0]["rho_m"]);
      EXPECT_GT(std::sqrt(var_b), 0.003) << b;  // millimetres of rho from the mount alone
      EXPECT_GT(var_b, 10.0 * var_a) << b;
      ++compared;
    }
    EXPECT_EQ(compared, 3);
  }
  // Every sigma zero: a map that would claim an exact calibration is refused.
  EXPECT_EQ(RunGroundline(map_command + " --out " + Quoted(dir / "zero.json"), dir, &out), 2)
      << out;
  // A map of another camera is refused by name.
  const calibration::CameraModel other = *calibration::CameraModel::Create(
      "LENSMODEL_PINHOLE", {280.0, 280.0, 159.5, 127.5}, 320, 256);
  ASSERT_TRUE(calibration::WriteMrcalCameraModel(dir / "other.cameramodel", other).ok());
  ASSERT_EQ(
      RunGroundline("calibrate bev-uncertainty --camera " + Quoted(dir / "other.cameramodel") +
                        " --extrinsics " + Quoted(dir / "extrinsics.yaml") +
                        " --sigma-pitch-deg 0.5 --out " + Quoted(dir / "other.json"),
                    dir, &out),
      0)
      << out;
  EXPECT_EQ(RunGroundline("extract " + Quoted(images) + " --camera " +
                              Quoted(dir / "camera.cameramodel") + " --bev-uncertainty " +
                              Quoted(dir / "other.json") + " --out " + Quoted(dir / "out_other"),
                          dir, &out),
            1)
      << out;
  EXPECT_NE(out.find("another camera model"), std::string::npos) << out;

  EXPECT_EQ(RunGroundline("extract --out " + Quoted(result), dir, &out), 2) << out;
  EXPECT_EQ(RunGroundline("extract " + Quoted(images) + " --camera " + Quoted(dir / "nope.yaml") +
                              " --out " + Quoted(result),
                          dir, &out),
            1)
      << out;
}

// Any camera, any mount: the BEV's extent and cell from the command line
// (by default the camera's floor footprint), and the mount from a ground
// homography in place of the extrinsics file.
TEST(ExtractCli, BevExtentAndGroundHomography) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("extract_cli_bev");
  const std::filesystem::path images = dir / "images";
  std::filesystem::create_directories(images);
  const calibration::CameraModel camera = *calibration::CameraModel::Create(
      "LENSMODEL_PINHOLE", {283.0, 283.0, 159.5, 127.5}, 320, 256);
  const calibration::CameraMount mount;
  ASSERT_TRUE(calibration::WriteMrcalCameraModel(dir / "camera.cameramodel", camera).ok());
  ASSERT_TRUE(calibration::WriteCameraMountYaml(mount, dir / "extrinsics.yaml").ok());
  const calibration::FloorProjection projection(camera, mount);
  cv::Mat image(256, 320, CV_8U);
  for (int v = 0; v < 256; ++v) {
    for (int u = 0; u < 320; ++u) {
      double sum = 0.0;
      for (int s = 0; s < 4; ++s) {
        core::Result<Eigen::Vector2d> p =
            projection.FloorPointOfPixel({u - 0.375 + 0.25 * s, v - 0.375 + 0.25 * (3 - s)});
        sum += (p.ok() && std::abs(p->y() + 0.20) <= 0.0375) ? 190.0 : 70.0;
      }
      image.at<std::uint8_t>(v, u) = static_cast<std::uint8_t>(sum / 4.0);
    }
  }
  ASSERT_TRUE(cv::imwrite((images / "frame0.png").string(), image));
  // The version-2 homography of this camera (normalized image -> floor).
  const Eigen::Matrix3d H = calibration::ImageToFloorHomography(calibration::FloorToImageHomography(
      calibration::BaseFromCamera(mount), Eigen::Matrix3d::Identity()));
  {
    std::ofstream file(dir / "homography.yaml");
    file.precision(17);
    file << "version: '2'\nhomography:\n";
    for (int r = 0; r < 3; ++r)
      file << "- [" << H(r, 0) << ", " << H(r, 1) << ", " << H(r, 2) << "]\n";
  }
  const std::string base = "extract " + Quoted(images) + " --camera " +
                           Quoted(dir / "camera.cameramodel") + " --png-every 0";
  const auto one_line = [](const std::filesystem::path& result) {
    std::ifstream jsonl(result / "lines.jsonl");
    std::string text;
    std::getline(jsonl, text);
    const nlohmann::json frame = nlohmann::json::parse(text);
    EXPECT_EQ(frame["lines"].size(), 1u) << text;
    return frame["lines"].empty() ? nlohmann::json() : frame["lines"][0];
  };
  std::string out;
  // Default: the footprint and 12 cm around it (the camera sees from 0.67 m
  // ahead; at a quarter of the resolution it resolves the floor to 3 cm per
  // pixel up to about 2 m).
  ASSERT_EQ(RunGroundline(base + " --extrinsics " + Quoted(dir / "extrinsics.yaml") + " --out " +
                              Quoted(dir / "footprint"),
                          dir, &out),
            0)
      << out;
  nlohmann::json summary = nlohmann::json::parse(std::ifstream(dir / "footprint/summary.json"));
  EXPECT_NEAR(summary["bev"]["x_m"][0].get<double>(), 0.67 - 0.12, 0.05) << summary.dump();
  EXPECT_GT(summary["bev"]["x_m"][1].get<double>(), 1.9);
  EXPECT_LT(summary["bev"]["x_m"][1].get<double>(), 2.45);
  EXPECT_EQ(summary["mount"]["source"], (dir / "extrinsics.yaml").string());
  const nlohmann::json by_footprint = one_line(dir / "footprint");
  EXPECT_NEAR(by_footprint["rho_m"].get<double>(), 0.20, 0.004);
  // Given: 1-2 m ahead, 0.5 m to each side, 2 cm cells.
  ASSERT_EQ(RunGroundline(base + " --extrinsics " + Quoted(dir / "extrinsics.yaml") +
                              " --bev-x 1 2 --bev-y -0.5 0.5 --bev-cell 0.02 --out " +
                              Quoted(dir / "given"),
                          dir, &out),
            0)
      << out;
  summary = nlohmann::json::parse(std::ifstream(dir / "given/summary.json"));
  EXPECT_EQ(summary["bev"]["rows"], 50);
  EXPECT_EQ(summary["bev"]["cols"], 50);
  const nlohmann::json by_given = one_line(dir / "given");
  EXPECT_NEAR(by_given["rho_m"].get<double>(), 0.20, 0.006);
  // The homography: the same mount, so the same line; the mount is written out.
  ASSERT_EQ(RunGroundline(base + " --homography " + Quoted(dir / "homography.yaml") + " --out " +
                              Quoted(dir / "homography"),
                          dir, &out),
            0)
      << out;
  const nlohmann::json by_homography = one_line(dir / "homography");
  EXPECT_NEAR(by_homography["rho_m"].get<double>(), by_footprint["rho_m"].get<double>(), 1e-6);
  EXPECT_NEAR(by_homography["alpha_rad"].get<double>(), by_footprint["alpha_rad"].get<double>(),
              1e-6);
  const core::Result<calibration::CameraMount> decomposed =
      calibration::ReadCameraMountYaml(dir / "homography/mount.yaml");
  ASSERT_TRUE(decomposed.ok()) << decomposed.message();
  EXPECT_TRUE(calibration::SameMount(*decomposed, mount, 1e-6));

  // Usage errors (exit 2) and a view of no floor (exit 1), each saying what.
  EXPECT_EQ(RunGroundline(base + " --bev-x 2 1 --out " + Quoted(dir / "bad"), dir, &out), 2);
  EXPECT_NE(out.find("x_m"), std::string::npos) << out;
  EXPECT_EQ(RunGroundline(base + " --bev-x 1 --out " + Quoted(dir / "bad"), dir, &out), 2) << out;
  EXPECT_EQ(
      RunGroundline(base + " --extrinsics " + Quoted(dir / "extrinsics.yaml") + " --homography " +
                        Quoted(dir / "homography.yaml") + " --out " + Quoted(dir / "bad"),
                    dir, &out),
      2)
      << out;
  EXPECT_EQ(
      RunGroundline(base + " --bev-x -3 -2 --bev-y -1 1 --out " + Quoted(dir / "bad"), dir, &out),
      1);
  EXPECT_NE(out.find("sees none"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "bad"));
}

// A real robot's version-2 homography (Duckietown dd24, calibrated on a floor
// board): its mount is decomposed (the board's left-handed frame mirrored) and
// the image is extracted in that frame; the camera is about 0.1 m high.
TEST(ExtractCli, RealDuckietownHomography) {
  GROUNDLINE_REQUIRE_DATA("floor/duckietown/extrinsics/dd24/real-world/scenario0");
  const std::filesystem::path data = ::groundline::testing::SharedDataDir() /
                                     "floor/duckietown/extrinsics/dd24/real-world/scenario0";
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("extract_cli_dd24");
  std::string out;
  ASSERT_EQ(RunGroundline("extract " + Quoted(data / "image-0.png") + " --camera " +
                              Quoted(data / "calibration-intrinsic-dd24.yaml") + " --homography " +
                              Quoted(data / "homography.yaml") + " --png-every 1 --out " +
                              Quoted(dir / "out"),
                          dir, &out),
            0)
      << out;
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(dir / "out/summary.json"));
  EXPECT_EQ(summary["frames"], 1);
  EXPECT_GT(summary["mount"]["height_m"].get<double>(), 0.05) << summary.dump();
  EXPECT_LT(summary["mount"]["height_m"].get<double>(), 0.20);
  EXPECT_NE(summary["mount"]["source"].get<std::string>().find("mirrored"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir / "out/mount.yaml"));
  EXPECT_TRUE(std::filesystem::exists(dir / "out/overlay_image-0.png"));
}

}  // namespace
}  // namespace groundline

namespace groundline {
namespace {

// A randomized simulated scene through `sim --randomize-nuisances` and
// `extract --dataset`: the simulator writes its nuisance truth, and extract
// accounts for every false line once, by the nuisance it lies along. The
// scene (zone B, 6 m, seed 5) is one whose frames hold false lines along cast
// and vehicle shadow edges and along no nuisance: the accounting has
// something to count in more than one class.
TEST(ExtractCli, FalseLinesPerNuisanceClass) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("extract_cli_nuisances");
  std::string out;
  ASSERT_EQ(RunGroundline("sim --zone B --length 6m --seed 5 --no-lidar --camera-rate 2 "
                          "--randomize-nuisances --threads 2 --out " +
                              Quoted(dir / "scene"),
                          dir, &out),
            0)
      << out;
  std::ifstream truth_file(dir / "scene" / "nuisance_truth.json");
  const nlohmann::json truth = nlohmann::json::parse(truth_file);
  EXPECT_EQ(truth["format"], "groundline-nuisance-truth");
  EXPECT_TRUE(truth["render"]["cast_shadows"].get<bool>());  // every scene has them
  EXPECT_FALSE(truth["segments_map"].empty());

  ASSERT_EQ(RunGroundline("extract --dataset " + Quoted(dir / "scene") + " --png-every 0 --out " +
                              Quoted(dir / "lines"),
                          dir, &out),
            0)
      << out;
  EXPECT_NE(out.find("nuisance class"), std::string::npos) << out;
  std::ifstream summary_file(dir / "lines" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(summary_file);
  ASSERT_TRUE(summary["by_nuisance"].contains("none")) << summary.dump(2);
  int false_lines = 0;
  int classes_with_false_lines = 0;
  for (const auto& [cls, s] : summary["by_nuisance"].items()) {
    false_lines += s["false_lines"].get<int>();
    if (s["false_lines"].get<int>() > 0) ++classes_with_false_lines;
  }
  EXPECT_GT(false_lines, 0) << summary.dump(2);
  EXPECT_GE(classes_with_false_lines, 2) << summary.dump(2);
  EXPECT_EQ(false_lines, summary["false_detections"].get<int>()) << summary.dump(2);
  // Each false line of lines.jsonl names its class; the counts agree.
  std::map<std::string, int> counted;
  std::ifstream lines(dir / "lines" / "lines.jsonl");
  for (std::string line; std::getline(lines, line);) {
    const nlohmann::json frame = nlohmann::json::parse(line);
    for (const nlohmann::json& l : frame.at("lines")) {
      if (l.contains("false_along")) ++counted[l["false_along"].get<std::string>()];
    }
  }
  int counted_total = 0;
  for (const auto& [cls, n] : counted) {
    ASSERT_TRUE(summary["by_nuisance"].contains(cls)) << cls;
    EXPECT_EQ(n, summary["by_nuisance"].at(cls).at("false_lines").get<int>()) << cls;
    counted_total += n;
  }
  EXPECT_EQ(counted_total, false_lines);
}

}  // namespace
}  // namespace groundline
