// Shared by the intrinsics tests: the 13 left views of OpenCV's chessboard
// set (../shared/data/calib/opencv_chessboard) detected with groundline's
// detector, and the board definition from calib_targets/targets.yaml.
#ifndef GROUNDLINE_TESTS_CALIBRATION_CALIBRATION_TEST_VIEWS_H_
#define GROUNDLINE_TESTS_CALIBRATION_CALIBRATION_TEST_VIEWS_H_

#include <gtest/gtest.h>

#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "groundline/calibration/board_detection.h"
#include "groundline/calibration/calib_target.h"
#include "groundline/calibration/intrinsic_calibration.h"
#include "test_data.h"

namespace groundline::calibration::testing {

inline CalibTarget TargetNamed(const std::string& name) {
  core::Result<std::vector<CalibTarget>> targets = ReadCalibTargets(GROUNDLINE_CALIB_TARGETS_FILE);
  EXPECT_TRUE(targets.ok()) << targets.message();
  core::Result<CalibTarget> target = FindCalibTarget(*targets, name);
  EXPECT_TRUE(target.ok()) << target.message();
  return *target;
}

// OpenCV's calibration sample's corner settings (the published reference
// was computed with them).
inline BoardDetectionOptions OpenCvSampleDetection() {
  BoardDetectionOptions options;
  options.chessboard_subpix_half_window_px = 11;
  options.chessboard_subpix_epsilon_px = 0.1;
  options.chessboard_subpix_iterations = 30;
  return options;
}

inline std::vector<CalibrationView> OpenCvLeftViews(
    const BoardGrid& grid, const BoardDetectionOptions& options = BoardDetectionOptions{}) {
  const CalibTarget target = TargetNamed("opencv_chessboard_9x6_25mm");
  std::vector<CalibrationView> views;
  for (int i = 1; i <= 14; ++i) {
    if (i == 10) continue;  // the set has no left10.jpg
    char name[32];
    std::snprintf(name, sizeof(name), "left%02d.jpg", i);
    const cv::Mat image = cv::imread(
        (groundline::testing::SharedDataDir() / "calib/opencv_chessboard" / name).string(),
        cv::IMREAD_GRAYSCALE);
    core::Result<BoardObservation> obs = DetectBoard(image, target, grid, options);
    EXPECT_TRUE(obs.ok()) << name << ": " << obs.message();
    if (obs.ok()) views.push_back({name, *obs});
  }
  return views;
}

}  // namespace groundline::calibration::testing

#endif  // GROUNDLINE_TESTS_CALIBRATION_CALIBRATION_TEST_VIEWS_H_
