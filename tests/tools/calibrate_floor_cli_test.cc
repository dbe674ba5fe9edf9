// End to end: `groundline sim-commissioning` then `groundline calibrate floor`,
// and the command's errors for bad inputs.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "cli_runner.h"
#include "groundline/calibration/calibration_report.h"
#include "groundline/calibration/camera_mount_yaml.h"
#include "groundline/calibration/mrcal_cameramodel_io.h"
#include "groundline/calibration/tag_layout.h"
#include "test_data.h"
#include "tools_under_test.h"

namespace groundline::testing {
namespace {

TEST(CalibrateFloorCli, RecoversTheSimulatedMountAndReportsErrors) {
  const std::filesystem::path dir = ScratchDir("floor");
  const std::filesystem::path scene = dir / "scene";
  std::string out;
  ASSERT_EQ(RunGroundline("sim-commissioning --small --poses 2 --seed 3 --out " + Quoted(scene),
                          dir, &out),
            0)
      << out;
  const std::string calibrate = "calibrate floor --images " + Quoted(scene / "images") +
                                " --layout " + Quoted(scene / "tag_layout.yaml") + " --camera " +
                                Quoted(scene / "camera.cameramodel") + " --out ";
  ASSERT_EQ(RunGroundline(calibrate + Quoted(dir / "cal"), dir, &out), 0) << out;
  EXPECT_NE(out.find("PASS"), std::string::npos) << out;

  const auto truth = calibration::ReadCameraMountYaml(scene / "true_extrinsics.yaml");
  const auto solved = calibration::ReadCameraMountYaml(dir / "cal" / "extrinsics.yaml");
  ASSERT_TRUE(truth.ok() && solved.ok()) << solved.message();
  EXPECT_NEAR(solved->height_m, truth->height_m, 0.5e-3);
  EXPECT_NEAR(solved->pitch_rad, truth->pitch_rad, 0.02 * M_PI / 180);
  EXPECT_NEAR(solved->roll_rad, truth->roll_rad, 0.02 * M_PI / 180);
  EXPECT_NEAR(solved->yaw_rad, truth->yaw_rad, 0.05 * M_PI / 180);
  const nlohmann::json report = nlohmann::json::parse(ReadText(dir / "cal" / "floor_report.json"));
  EXPECT_EQ(report["verdict"], "PASS");
  EXPECT_EQ(report["bev_error"].size(), 3u);
  EXPECT_EQ(report["images"].size(), 2u);
  EXPECT_LT(report["rms_px"].get<double>(), 0.5);
  EXPECT_GT(report["mount"]["height_mm"]["sigma3"].get<double>(), 0.0);
  EXPECT_NE(ReadText(dir / "cal" / "floor_report.html").find("<svg"), std::string::npos);
  // The BEV uncertainty map: in the report (mm per cell) and as the file
  // perception reads (covariances), for the same grid.
  const nlohmann::json& bev = report["bev_uncertainty"];
  EXPECT_EQ(bev["cells_x"], 20);
  EXPECT_EQ(bev["cells_y"], 20);
  EXPECT_FALSE(bev["includes_intrinsics"].get<bool>());
  EXPECT_GT(bev["worst_rms_mm"].get<double>(), 0.0);
  const nlohmann::json map = nlohmann::json::parse(ReadText(dir / "cal" / "bev_uncertainty.json"));
  EXPECT_EQ(map["format"], "groundline.bev_uncertainty");
  ASSERT_EQ(map["covariance_m2"].size(), 400u);
  int seen = 0;
  for (std::size_t i = 0; i < 400; ++i) {
    EXPECT_EQ(map["covariance_m2"][i].is_null(), bev["rms_mm"][i].is_null()) << i;
    if (map["covariance_m2"][i].is_null()) continue;
    ++seen;
    const double trace =
        map["covariance_m2"][i][0].get<double>() + map["covariance_m2"][i][2].get<double>();
    EXPECT_NEAR(bev["rms_mm"][i].get<double>(), 1e3 * std::sqrt(trace), 0.051) << i;
  }
  EXPECT_GT(seen, 10);
  EXPECT_NE(out.find("BEV uncertainty map (mount only)"), std::string::npos) << out;
  EXPECT_NE(ReadText(dir / "cal" / "floor_report.html").find("BEV uncertainty map"),
            std::string::npos);

  // An image without tags is named and skipped.
  const cv::Mat blank(384, 480, CV_8UC1, cv::Scalar(90));
  ASSERT_TRUE(cv::imwrite((scene / "images" / "pose_001.png").string(), blank));
  // The one image left sees too little of the mat at the bottom of the image:
  // the coverage check (and only it) fails and names the quadrants.
  EXPECT_EQ(RunGroundline(calibrate + Quoted(dir / "cal1"), dir, &out), 1) << out;
  EXPECT_NE(out.find("pose_001.png: no tag of the layout found; image skipped"), std::string::npos)
      << out;
  const nlohmann::json one = nlohmann::json::parse(ReadText(dir / "cal1" / "floor_report.json"));
  ASSERT_FALSE(one["failures"].empty());
  for (const auto& f : one["failures"]) {
    EXPECT_NE(f.get<std::string>().find("image quadrant"), std::string::npos) << f;
  }

  // pose_001 replaced by pose_000 shows its tags at the wrong vehicle pose: an
  // outlier image that fails the RMS threshold and is named.
  std::filesystem::copy_file(scene / "images" / "pose_000.png", scene / "images" / "pose_001.png",
                             std::filesystem::copy_options::overwrite_existing);
  EXPECT_EQ(RunGroundline(calibrate + Quoted(dir / "cal2"), dir, &out), 1) << out;
  EXPECT_NE(out.find("pose_001.png: corner RMS"), std::string::npos) << out;

  // A malformed layout names the file, line and field.
  std::ofstream(dir / "bad.yaml")
      << "format: groundline-tag-layout\nversion: \"1.0\"\n"
         "family: tag36h11\nframe: floor\ntags:\n"
         "  - {id: 1, size_m: zero, pose: {x_m: 0, y_m: 0, yaw_rad: 0}}\n";
  const std::string bad = "calibrate floor --images " + Quoted(scene / "images") + " --layout " +
                          Quoted(dir / "bad.yaml") + " --camera " +
                          Quoted(scene / "camera.cameramodel") + " --out " + Quoted(dir / "cal3");
  EXPECT_EQ(RunGroundline(bad, dir, &out), 1);
  EXPECT_NE(out.find("bad.yaml:6: field 'tags[0].size_m'"), std::string::npos) << out;

  // A base_link layout over a directory of tagless images: nothing to solve.
  std::filesystem::create_directories(dir / "blank");
  std::ofstream(dir / "base.yaml")
      << "format: groundline-tag-layout\nversion: \"1.0\"\n"
         "family: tag36h11\nframe: base_link\ntags:\n"
         "  - {id: 1, size_m: 0.2, pose: {x_m: 1, y_m: 0, yaw_rad: 0}}\n";
  EXPECT_EQ(RunGroundline("calibrate floor --images " + Quoted(dir / "blank") + " --layout " +
                              Quoted(dir / "base.yaml") + " --camera " +
                              Quoted(scene / "camera.cameramodel") + " --out " + Quoted(dir / "c4"),
                          dir, &out),
            1);
  EXPECT_NE(out.find("no image files"), std::string::npos) << out;
}

// The report of the whole flow: verdict, failed checks with advice, 3-sigma
// bounds, per-tag residuals, the rectified floor, thresholds from a config
// (flags override it), the intrinsics folded in; and the input errors.
TEST(CalibrateFloorCli, CommissioningReportCarriesVerdictAdviceBoundsAndTheRectifiedFloor) {
  if (::groundline::testing::Sanitized()) {
    // CI time: a Debug executable solving and rectifying a rendered scene (~60 s under ASan);
    // FloorRectification covers the geometry under ASan.
    GTEST_SKIP() << "too slow under AddressSanitizer (Debug); runs in the release build";
  }
  const std::filesystem::path dir = ScratchDir("floor_report");
  const std::filesystem::path scene = dir / "scene";
  std::string out;
  ASSERT_EQ(RunGroundline("sim-commissioning --small --poses 2 --seed 5 --out " + Quoted(scene),
                          dir, &out),
            0)
      << out;
  std::ofstream(dir / "config.yaml") << "floor_report:\n  max_tag_rms_px: 0.9\n"
                                        "  max_bev_error_2m_mm: 4\n";
  // An intrinsics report of the scene's own camera (it must be: the
  // commissioning report refuses another camera's).
  const calibration::CameraModel scene_camera =
      calibration::ReadMrcalCameraModel(scene / "camera.cameramodel")->camera;
  const auto intrinsics_json = [&](int width, int height, const std::string& fingerprint) {
    return std::string(R"({"format": "groundline-intrinsics-report", "verdict": "FAIL",)") +
           R"( "failures": ["bottom-left quadrant: 3 corners < 10"],)"
           R"( "advice": ["take more views with the board in the bottom-left of the image"],)"
           R"( "target": "grid", "lens_model": ")" +
           scene_camera.lens_model() +
           R"(", "rms_px": 0.21, "worst_px": 1.1, "views": [{}, {}],)"
           R"( "quadrant_corners": {"top_left": 40, "top_right": 41, "bottom_left": 3,)"
           R"( "bottom_right": 44}, "imager_size_px": [)" +
           std::to_string(width) + ", " + std::to_string(height) +
           R"(], "intrinsics": [1, 2, 3, 4], "camera_fingerprint": ")" + fingerprint + "\"}";
  };
  std::ofstream(dir / "intrinsics.json")
      << intrinsics_json(scene_camera.width_px(), scene_camera.height_px(),
                         calibration::CameraFingerprint(scene_camera));
  std::ofstream(dir / "intrinsics_640.json") << intrinsics_json(640, 480, "0123456789abcdef");
  std::ofstream(dir / "intrinsics_other.json")
      << intrinsics_json(scene_camera.width_px(), scene_camera.height_px(), "0123456789abcdef");
  const std::string calibrate = "calibrate floor --images " + Quoted(scene / "images") +
                                " --camera " + Quoted(scene / "camera.cameramodel") + " --config " +
                                Quoted(dir / "config.yaml") + " --layout ";
  const std::string layout = Quoted(scene / "tag_layout.yaml");
  // Another camera's intrinsics: refused before anything is solved (exit 1).
  ASSERT_EQ(RunGroundline(calibrate + layout + " --intrinsics-report " +
                              Quoted(dir / "intrinsics_640.json") + " --out " + Quoted(dir / "x"),
                          dir, &out),
            1)
      << out;
  EXPECT_NE(out.find("are not the same camera: the report is for a 640x480 px imager, the "
                     "camera model is " +
                     std::to_string(scene_camera.width_px()) + "x" +
                     std::to_string(scene_camera.height_px()) + " px"),
            std::string::npos)
      << out;
  EXPECT_EQ(out.find("commissioning: PASS"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "x" / "floor_report.json"));
  ASSERT_EQ(RunGroundline(calibrate + layout + " --intrinsics-report " +
                              Quoted(dir / "intrinsics_other.json") + " --out " + Quoted(dir / "y"),
                          dir, &out),
            1);
  EXPECT_NE(out.find("model fingerprint 0123456789abcdef in the report"), std::string::npos) << out;
  // Floor PASS, intrinsics FAIL: the commissioning fails (exit 1).
  ASSERT_EQ(RunGroundline(calibrate + layout + " --intrinsics-report " +
                              Quoted(dir / "intrinsics.json") + " --out " + Quoted(dir / "a"),
                          dir, &out),
            1)
      << out;
  EXPECT_NE(out.find("commissioning: FAIL"), std::string::npos) << out;
  nlohmann::json j = nlohmann::json::parse(ReadText(dir / "a" / "floor_report.json"));
  EXPECT_EQ(j["verdict"], "PASS") << j["failures"];
  EXPECT_EQ(j["overall_verdict"], "FAIL");
  EXPECT_EQ(j["intrinsics"]["verdict"], "FAIL");
  EXPECT_EQ(j["thresholds"]["max_tag_rms_px"], 0.9);
  EXPECT_EQ(j["thresholds"]["max_bev_error_2m_mm"], 4.0);
  const nlohmann::json& height = j["mount"]["height_mm"];
  EXPECT_LT(height["lower_3sigma"].get<double>(), height["value"].get<double>());
  EXPECT_GT(height["upper_3sigma"].get<double>(), height["value"].get<double>());
  EXPECT_GE(j["covariance"]["sigma_px"].get<double>(), 0.3);
  EXPECT_FALSE(j["tags"].empty());
  EXPECT_GT(j["rectified_floor"]["width_px"].get<int>(), 100);
  const std::string html = ReadText(dir / "a" / "floor_report.html");
  EXPECT_NE(html.find("<image width="), std::string::npos);
  EXPECT_NE(html.find("href='data:image/png;base64,iVBORw0KGgo"), std::string::npos);
  EXPECT_NE(html.find("Camera commissioning"), std::string::npos);
  EXPECT_NE(html.find("take more views with the board in the bottom-left"), std::string::npos);

  // A flag overrides the config: an unreachable BEV limit fails with advice.
  EXPECT_EQ(RunGroundline(calibrate + layout + " --max-bev-error 0.001 --out " + Quoted(dir / "b"),
                          dir, &out),
            1);
  EXPECT_NE(out.find("to do: the mount is too uncertain"), std::string::npos) << out;
  j = nlohmann::json::parse(ReadText(dir / "b" / "floor_report.json"));
  EXPECT_EQ(j["verdict"], "FAIL");
  EXPECT_EQ(j["thresholds"]["max_tag_rms_px"], 0.9);
  ASSERT_FALSE(j["failures"].empty());
  EXPECT_NE(j["failures"][0].get<std::string>().find("BEV error at 2 m"), std::string::npos);
  EXPECT_FALSE(j["advice"].empty());

  // A config error names the file, line and key.
  std::ofstream(dir / "bad_config.yaml") << "floor_report:\n  max_rms: 0.4\n";
  EXPECT_EQ(RunGroundline("calibrate floor --images " + Quoted(scene / "images") + " --camera " +
                              Quoted(scene / "camera.cameramodel") + " --config " +
                              Quoted(dir / "bad_config.yaml") + " --layout " + layout + " --out " +
                              Quoted(dir / "c"),
                          dir, &out),
            1);
  EXPECT_NE(out.find("bad_config.yaml:2: key 'floor_report.max_rms': unknown key"),
            std::string::npos)
      << out;

  // A layout tag that no image shows is named; the calibration still runs.
  calibration::TagLayout extra = calibration::ReadTagLayout(scene / "tag_layout.yaml").value();
  extra.tags.push_back({500, 0.2, core::SE2(9.0, 9.0, 0.0)});
  ASSERT_TRUE(calibration::WriteTagLayout(extra, dir / "extra.yaml").ok());
  EXPECT_EQ(RunGroundline(calibrate + Quoted(dir / "extra.yaml") + " --out " + Quoted(dir / "d"),
                          dir, &out),
            0)
      << out;
  EXPECT_NE(out.find("warning: tag 500 of the layout was never seen"), std::string::npos) << out;

  // A listed image that is missing is an error naming it.
  calibration::TagLayout missing = calibration::ReadTagLayout(scene / "tag_layout.yaml").value();
  missing.vehicle_poses[1].image = "pose_999.png";
  ASSERT_TRUE(calibration::WriteTagLayout(missing, dir / "missing.yaml").ok());
  EXPECT_EQ(RunGroundline(calibrate + Quoted(dir / "missing.yaml") + " --out " + Quoted(dir / "e"),
                          dir, &out),
            1);
  EXPECT_NE(out.find("pose_999.png: cannot read the image"), std::string::npos) << out;
}

}  // namespace
}  // namespace groundline::testing
