#include "groundline/calibration/self_calibration_history.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "groundline/core/angles.h"
#include "test_data.h"

namespace groundline::calibration {
namespace {

using core::kDegToRad;

// A health.jsonl of a short run: a keyframe before the self-calibration
// had a field, three estimates, the last one with the alarm.
std::filesystem::path WriteHealth(const std::filesystem::path& dir, const std::string& extra = "") {
  const std::filesystem::path path = dir / "health.jsonl";
  std::ofstream out(path);
  out << R"({"stamp_s":0.5,"mode":"lines"})" << "\n";
  const auto line = [&](double t, double pitch_deg, double height_m, int windows, bool alarm) {
    out << "{\"stamp_s\":" << t << ",\"selfcal_pitch_deg\":" << pitch_deg
        << ",\"selfcal_roll_deg\":0.1,\"selfcal_height_m\":" << height_m
        << ",\"selfcal_yaw_deg\":-0.2,\"selfcal_pitch_sigma_deg\":0.01,"
           "\"selfcal_roll_sigma_deg\":0.02,\"selfcal_height_sigma_m\":0.0005,"
           "\"selfcal_yaw_sigma_deg\":0.05,\"selfcal_alarm\":"
        << (alarm ? "true,\"selfcal_alarm_message\":\"roll changed by 0.4 deg\"" : "false")
        << ",\"selfcal_windows\":" << windows << ",\"selfcal_steps\":0}\n";
  };
  line(1.0, 42.4, 0.58, 0, false);
  line(2.0, 42.41, 0.5795, 1, false);
  line(3.0, 42.9, 0.5790, 2, true);
  out << extra;
  return path;
}

TEST(SelfCalibrationHistory, ReadsTheEstimateOfEveryKeyframeInTheEstimatorsUnits) {
  const auto dir = ::groundline::testing::ScratchDir("selfcal_history_read");
  const auto history = ReadSelfCalibrationHistory(WriteHealth(dir));
  ASSERT_TRUE(history.ok()) << history.message();
  ASSERT_EQ(history->size(), 3u);  // the line without selfcal fields is skipped
  const SelfCalibrationSample& s = history->back();
  EXPECT_DOUBLE_EQ(s.stamp_s, 3.0);
  EXPECT_NEAR(s.value(kMountPitch), 42.9 * kDegToRad, 1e-12);
  EXPECT_NEAR(s.value(kMountHeight), 0.579, 1e-12);
  EXPECT_NEAR(s.sigma(kMountRoll), 0.02 * kDegToRad, 1e-12);
  EXPECT_TRUE(s.alarm);
  EXPECT_EQ(s.alarm_message, "roll changed by 0.4 deg");
  EXPECT_EQ(s.windows, 2);
}

TEST(SelfCalibrationHistory, ErrorsNameTheFileLineAndField) {
  const auto dir = ::groundline::testing::ScratchDir("selfcal_history_errors");
  auto bad = ReadSelfCalibrationHistory(
      WriteHealth(dir, R"({"stamp_s":4,"selfcal_pitch_deg":"x"})" "\n"));
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("health.jsonl:5"), std::string::npos) << bad.message();
  EXPECT_NE(bad.message().find("selfcal_pitch_deg"), std::string::npos) << bad.message();
  bad = ReadSelfCalibrationHistory(WriteHealth(
      dir, R"({"stamp_s":4,"selfcal_pitch_deg":1,"selfcal_roll_deg":0,"selfcal_height_m":0.5,)"
           R"("selfcal_yaw_deg":0,"selfcal_pitch_sigma_deg":0.1,"selfcal_roll_sigma_deg":0.1,)"
           R"("selfcal_height_sigma_m":0.001,"selfcal_yaw_sigma_deg":0.1,"selfcal_alarm":false,)"
           R"("selfcal_windows":-2,"selfcal_steps":0})" "\n"));
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("selfcal_windows"), std::string::npos) << bad.message();
  bad = ReadSelfCalibrationHistory(WriteHealth(dir, "not json\n"));
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("health.jsonl:5: expected one JSON object"), std::string::npos)
      << bad.message();
  {
    std::ofstream out(dir / "health.jsonl");
    out << R"({"stamp_s":0.5,"mode":"lines"})" << "\n";
  }
  bad = ReadSelfCalibrationHistory(dir / "health.jsonl");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("not self-calibrated"), std::string::npos) << bad.message();
}

TEST(SelfCalibrationHistory, ErrorsAgainstAPiecewiseConstantTruth) {
  const auto dir = ::groundline::testing::ScratchDir("selfcal_history_truth");
  const auto history = ReadSelfCalibrationHistory(WriteHealth(dir));
  ASSERT_TRUE(history.ok());
  // The truth steps 0.5 deg of pitch at 2.5 s; its roll is 0.1 deg from the
  // estimate's, over 3 sigma (0.06 deg).
  std::vector<core::CameraExtrinsicsRecord> truth(2);
  truth[0] = {0.0, 0.58, 42.4 * kDegToRad, 0.0, -0.2 * kDegToRad, 0.42, 0.0};
  truth[1] = truth[0];
  truth[1].stamp_s = 2.5;
  truth[1].pitch_rad = 42.9 * kDegToRad;
  const SelfCalibrationErrors e = CompareWithTruth(*history, truth);
  EXPECT_EQ(e.samples, 2);  // the sample before the first window is the commissioned mount
  EXPECT_NEAR(e.max_abs(kMountPitch), 0.01 * kDegToRad, 1e-12);
  EXPECT_NEAR(e.max_abs(kMountHeight), 0.001, 1e-12);
  EXPECT_NEAR(e.rms(kMountHeight), std::sqrt((0.0005 * 0.0005 + 0.001 * 0.001) / 2), 1e-12);
  EXPECT_DOUBLE_EQ(e.within_3_sigma(kMountPitch), 1.0);   // 0.01 deg against 3 x 0.01
  EXPECT_DOUBLE_EQ(e.within_3_sigma(kMountHeight), 1.0);  // 1 mm against 3 x 0.5 mm
  EXPECT_DOUBLE_EQ(e.within_3_sigma(kMountRoll), 0.0);    // 0.1 deg against 3 x 0.02
  EXPECT_NEAR(e.rms(kMountRoll), 0.1 * kDegToRad, 1e-12);
  EXPECT_EQ(CompareWithTruth(*history, truth, 2.5).samples, 1);
}

TEST(SelfCalibrationHistory, ThePageHasAPanelPerComponentTheTruthAndTheAlarms) {
  const auto dir = ::groundline::testing::ScratchDir("selfcal_history_html");
  const auto history = ReadSelfCalibrationHistory(WriteHealth(dir));
  ASSERT_TRUE(history.ok());
  std::vector<core::CameraExtrinsicsRecord> truth = {
      {0.0, 0.58, 42.4 * kDegToRad, 0.0, 0.0, 0.42, 0.0}};
  const std::string html = SelfCalibrationHistoryHtml(*history, &truth, "run <1>");
  for (const char* component : {"pitch", "roll", "height", "yaw"}) {
    EXPECT_NE(html.find("data-component='" + std::string(component) + "'"), std::string::npos)
        << component;
  }
  const auto count = [&](const std::string& what) {
    int n = 0;
    for (std::size_t at = html.find(what); at != std::string::npos; at = html.find(what, at + 1))
      ++n;
    return n;
  };
  EXPECT_EQ(count("class='estimate'"), 4);
  EXPECT_EQ(count("class='band'"), 4);
  EXPECT_EQ(count("class='truth'"), 4);
  EXPECT_EQ(count("class='alarm'"), 4);  // one alarmed keyframe, one mark per panel
  // The alarm as one episode: when it was raised, that it stood to the end.
  EXPECT_NE(html.find("Raised at 3.0 s, standing at the end of the run: roll changed by 0.4 deg"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("the alarm stood at 1 keyframes, raised first at 3.0 s"), std::string::npos);
  EXPECT_NE(html.find("run &lt;1&gt;"), std::string::npos);  // the title escaped
  EXPECT_EQ(SelfCalibrationHistoryHtml(*history, nullptr, "x").find("class='truth'"),
            std::string::npos);
}

// The mount the lines were read under can lie beyond every estimate (a
// suspected step's, before the windows confirm it): the panel's range holds
// it, so its line is drawn where it is instead of flat on the panel's edge.
TEST(SelfCalibrationHistory, ThePanelsRangeHoldsTheMountTheLinesWereReadUnder) {
  const auto dir = ::groundline::testing::ScratchDir("selfcal_history_observed");
  const std::filesystem::path path = dir / "health.jsonl";
  {
    std::ofstream out(path);
    // Estimates within 0.5 mm of 580 mm; the lines read 10 and 15 mm lower
    // at the second and third keyframe.
    const double observed_mm[] = {580.0, 570.0, 565.0, 580.0};
    for (int k = 0; k < 4; ++k) {
      out << "{\"stamp_s\":" << k + 1 << ",\"selfcal_pitch_deg\":42.4,\"selfcal_roll_deg\":0,"
          << "\"selfcal_height_m\":" << 0.58 - 0.0001 * k << ",\"selfcal_yaw_deg\":0,"
          << "\"selfcal_pitch_sigma_deg\":0.01,\"selfcal_roll_sigma_deg\":0.01,"
             "\"selfcal_height_sigma_m\":0.0002,\"selfcal_yaw_sigma_deg\":0.01,"
             "\"selfcal_alarm\":false,\"selfcal_windows\":"
          << k + 1 << ",\"selfcal_steps\":0,\"selfcal_observed_pitch_deg\":42.4,"
          << "\"selfcal_observed_roll_deg\":0,\"selfcal_observed_height_m\":"
          << observed_mm[k] / 1000.0 << ",\"selfcal_observed_yaw_deg\":0}\n";
    }
  }
  const auto history = ReadSelfCalibrationHistory(path);
  ASSERT_TRUE(history.ok()) << history.status().message();
  const std::string html = SelfCalibrationHistoryHtml(*history, nullptr, "run");
  const std::size_t panel = html.find("data-component='height'");
  ASSERT_NE(panel, std::string::npos);
  const std::string key = "class='observed' points='";
  const std::size_t at = html.find(key, panel);
  ASSERT_NE(at, std::string::npos) << html;
  std::istringstream points(
      html.substr(at + key.size(), html.find('\'', at + key.size()) - at - key.size()));
  std::vector<double> ys;
  double x = 0.0, y = 0.0;
  char comma = 0;
  while (points >> x >> comma >> y) ys.push_back(y);
  ASSERT_EQ(ys.size(), 4u);
  // SVG y grows downwards: 565 mm below 570 mm below the estimates.
  EXPECT_GT(ys[1], ys[0] + 1.0);
  EXPECT_GT(ys[2], ys[1] + 1.0);
  EXPECT_NEAR(ys[3], ys[0], 1e-9);
}

}  // namespace
}  // namespace groundline::calibration
