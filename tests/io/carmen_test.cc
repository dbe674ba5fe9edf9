// CARMEN parsing on hand-written logs: every message type, the old-format
// laser geometry, malformed lines in strict and lenient mode, the streaming
// callback, and the scan trajectory.
#include "groundline/io/carmen.h"

#include <gtest/gtest.h>

#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "groundline/io/carmen_trajectory.h"
#include "test_data.h"
#include "test_units.h"

namespace groundline::io {
namespace {

namespace fs = std::filesystem;
using groundline::testing::ScratchDir;
using ::groundline::testing::kPi;

fs::path WriteLog(const std::string& name, const std::vector<std::string>& lines) {
  const fs::path path = ScratchDir(name) / (name + ".clf");
  std::ofstream out(path);
  for (const std::string& line : lines) out << line << '\n';
  return path;
}

CarmenReadOptions Strict() {
  CarmenReadOptions options;
  options.strict = true;
  return options;
}

// A well-formed log with every message type the reader knows, plus an
// unknown type, comments and a blank line.
std::vector<std::string> GoodLines() {
  return {
      "# message_name [message contents] ipc_timestamp ipc_hostname logger_timestamp",
      "PARAM robot_use_laser on nohost 0",                              // 2: old form
      "PARAM robot_frontlaser_offset 0.22 1.5 host 0.01",               // 3: with ipc
      "PARAM logger_comment two words 1.5 host 0.01",                   // 4: value with a space
      "SYNC start 1.0 host 0.0",                                        // 5
      "ODOM 1.0 2.0 0.5 0.3 -0.1 0.0 10.0 host 0.1",                    // 6
      "FLASER 3 1.5 2.5 3.5 1.1 2.1 0.6 1.0 2.0 0.6 10.1 host 0.2",     // 7
      "",                                                               // 8
      "RLASER 2 4.0 5.0 1.0 2.0 3.14 1.0 2.0 0.5 10.2 host 0.3",        // 9
      "RAWLASER1 0 -1.5 3.0 0.5 30.0 0.01 1 3 1 2 3 2 9 8 10.3 h 0.4",  // 10
      "ROBOTLASER1 0 -1.0 2.0 1.0 40.0 0.01 0 3 7 8 9 0 "
      "1.22 2.0 0.5 1.0 2.0 0.5 0.4 0.05 0.1 0.2 0.3 10.4 host 0.5",  // 11
      "TRUEPOS 5 6 0.1 1 2 0.2 10.5 host 0.6",                        // 12
      "NMEAGGA 1 2 3 4 10.6 host 0.7",                                // 13: unknown
  };
}

TEST(CarmenReader, ParsesEveryKnownMessageType) {
  core::Result<CarmenLog> log = ReadCarmenLog(WriteLog("good", GoodLines()), Strict());
  ASSERT_TRUE(log.ok()) << log.message();
  const CarmenReadSummary& s = log->summary;
  EXPECT_EQ(s.lines, 13);
  EXPECT_EQ(s.comment_lines, 1);
  EXPECT_EQ(s.blank_lines, 1);
  EXPECT_EQ(s.Count("PARAM"), 3);
  EXPECT_EQ(s.Count("SYNC"), 1);
  EXPECT_EQ(s.Count("NMEAGGA"), 1);
  EXPECT_EQ(s.Count("ROBOTLASER1"), 1);
  EXPECT_EQ(s.unknown_messages, 1);
  EXPECT_EQ(s.skipped_line_count, 0);

  EXPECT_EQ(log->params.at("robot_use_laser"), "on");
  EXPECT_EQ(log->params.at("robot_frontlaser_offset"), "0.22");
  EXPECT_EQ(log->params.at("logger_comment"), "two words");

  ASSERT_EQ(log->odometry.size(), 1u);
  const CarmenOdometry& odom = log->odometry[0];
  EXPECT_EQ(odom.line, 6);
  EXPECT_TRUE(odom.pose.IsApprox(core::SE2(1.0, 2.0, 0.5)));
  EXPECT_DOUBLE_EQ(odom.tv_mps, 0.3);
  EXPECT_DOUBLE_EQ(odom.rv_radps, -0.1);
  EXPECT_DOUBLE_EQ(odom.stamp_s, 10.0);
  EXPECT_DOUBLE_EQ(odom.logger_stamp_s, 0.1);

  ASSERT_EQ(log->scans.size(), 4u);
  const CarmenLaserScan& front = log->scans[0];
  EXPECT_EQ(front.message, CarmenLaserMessage::kFlaser);
  EXPECT_EQ(front.laser_id, 1);
  EXPECT_EQ(front.ranges_m, (std::vector<double>{1.5, 2.5, 3.5}));
  EXPECT_TRUE(front.laser_pose->IsApprox(core::SE2(1.1, 2.1, 0.6)));
  EXPECT_TRUE(front.robot_pose->IsApprox(core::SE2(1.0, 2.0, 0.6)));
  EXPECT_DOUBLE_EQ(front.stamp_s, 10.1);

  const CarmenLaserScan& rear = log->scans[1];
  EXPECT_EQ(rear.message, CarmenLaserMessage::kRlaser);
  EXPECT_EQ(rear.laser_id, 2);
  EXPECT_EQ(CarmenLaserMessageName(rear), "RLASER");

  const CarmenLaserScan& raw = log->scans[2];
  EXPECT_EQ(raw.message, CarmenLaserMessage::kRawLaser);
  EXPECT_EQ(CarmenLaserMessageName(raw), "RAWLASER1");
  EXPECT_DOUBLE_EQ(raw.angle_min_rad, -1.5);
  EXPECT_DOUBLE_EQ(raw.angle_increment_rad, 0.5);
  EXPECT_DOUBLE_EQ(raw.max_range_m, 30.0);
  EXPECT_EQ(raw.ranges_m, (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(raw.remissions, (std::vector<double>{9, 8}));
  EXPECT_FALSE(raw.laser_pose.has_value());
  EXPECT_FALSE(raw.robot_pose.has_value());

  const CarmenLaserScan& robot = log->scans[3];
  EXPECT_EQ(robot.message, CarmenLaserMessage::kRobotLaser);
  EXPECT_EQ(robot.ranges_m, (std::vector<double>{7, 8, 9}));
  EXPECT_TRUE(robot.remissions.empty());
  EXPECT_TRUE(robot.laser_pose->IsApprox(core::SE2(1.22, 2.0, 0.5)));
  EXPECT_TRUE(robot.robot_pose->IsApprox(core::SE2(1.0, 2.0, 0.5)));
  EXPECT_DOUBLE_EQ(robot.tv_mps, 0.4);
  EXPECT_DOUBLE_EQ(robot.rv_radps, 0.05);
  EXPECT_DOUBLE_EQ(robot.stamp_s, 10.4);

  ASSERT_EQ(log->true_poses.size(), 1u);
  EXPECT_TRUE(log->true_poses[0].true_pose.IsApprox(core::SE2(5, 6, 0.1)));
  EXPECT_TRUE(log->true_poses[0].odom_pose.IsApprox(core::SE2(1, 2, 0.2)));
}

TEST(CarmenReader, OldFormatGeometryFollowsCarmenGuess) {
  EXPECT_DOUBLE_EQ(GuessOldFormatAngleIncrementRad(180), kPi / 180);
  EXPECT_DOUBLE_EQ(GuessOldFormatAngleIncrementRad(181), kPi / 180);
  EXPECT_DOUBLE_EQ(GuessOldFormatAngleIncrementRad(360), kPi / 360);
  EXPECT_DOUBLE_EQ(GuessOldFormatAngleIncrementRad(361), kPi / 360);
  EXPECT_DOUBLE_EQ(GuessOldFormatAngleIncrementRad(401), kPi / 720);
  EXPECT_DOUBLE_EQ(GuessOldFormatAngleIncrementRad(101), kPi / 100);
  EXPECT_EQ(GuessOldFormatAngleIncrementRad(1), 0.0);

  const fs::path path = WriteLog("geometry", {"FLASER 3 1 2 3 0 0 0 0 0 0 1.0 h 0.0"});
  core::Result<CarmenLog> guessed = ReadCarmenLog(path, Strict());
  ASSERT_TRUE(guessed.ok()) << guessed.message();
  EXPECT_DOUBLE_EQ(guessed->scans[0].angle_min_rad, -kPi / 2);
  EXPECT_DOUBLE_EQ(guessed->scans[0].angle_increment_rad, kPi / 2);  // pi / (3 - 1)

  CarmenReadOptions options = Strict();
  options.old_format_angle_min_rad = -1.0;
  options.old_format_angle_increment_rad = 0.25;
  options.old_format_max_range_m = 30.0;
  core::Result<CarmenLog> overridden = ReadCarmenLog(path, options);
  ASSERT_TRUE(overridden.ok()) << overridden.message();
  EXPECT_DOUBLE_EQ(overridden->scans[0].angle_min_rad, -1.0);
  EXPECT_DOUBLE_EQ(overridden->scans[0].BeamAngleRad(2), -0.5);
  EXPECT_DOUBLE_EQ(overridden->scans[0].max_range_m, 30.0);
}

struct MalformedCase {
  std::string line;
  std::string field;  // what the error must name
};

// Each line is broken in one way; the error must name its field.
std::vector<MalformedCase> MalformedCases() {
  return {
      // too few readings for the count (count 4, 3 ranges): the count overruns
      {"FLASER 4 1 2 3 0 0 0 0 0 0 1.0 h 0.0",
       "FLASER field 'num_readings' (field 2): count 4 "
       "overruns the line"},
      // remission count running past the end of the line
      {"RAWLASER1 0 -1.5 3.0 0.5 30.0 0.01 1 2 1 2 50 9 8 1.0 h 0.0",
       "RAWLASER1 field 'num_remissions' (field 12): count 50 overruns"},
      // absurd and negative counts
      {"FLASER 999999999 1 2", "'num_readings' (field 2): expected a count in [0, 100000]"},
      {"FLASER -3 1 2 3 0 0 0 0 0 0 1.0 h 0.0", "'num_readings' (field 2): expected a count"},
      // a non-numeric range and a non-numeric pose field
      {"FLASER 3 1.0 abc 2.0 0 0 0 0 0 0 1.0 h 0.0",
       "FLASER field 'range[1]' (field 4): expected a finite number, got 'abc'"},
      {"ODOM 1.0 1.0.0 0.5 0 0 0 1.0 h 0.0", "ODOM field 'y' (field 3)"},
      {"FLASER 3 1.0 nan 2.0 0 0 0 0 0 0 1.0 h 0.0", "'range[1]' (field 4): expected a finite"},
      {"ROBOTLASER1 0 -1 2 1 40 0.01 0 1 7 0 1 2 0.5 1 x 0.5 0 0 0 0 0 1.0 h 0.0",
       "ROBOTLASER1 field 'robot_pose_y' (field 16)"},
      // truncated lines (the writer stopped mid-line)
      {"ODOM 1.0 2.0 0.5 0.3", "ODOM field 'rv' (field 6): missing"},
      {"FLASER 180 1.0 2.0 3.0", "'num_readings' (field 2): count 180 overruns"},
      {"TRUEPOS 5 6 0.1 1 2 0.2 10.5 host", "TRUEPOS field 'logger_timestamp' (field 10): missing"},
      // more values than the count says
      {"ODOM 1 2 0.5 0 0 0 1.0 h 0.0 7", "ODOM: 1 extra fields after 'logger_timestamp'"},
      {"FLASER 2 1 2 3 0 0 0 0 0 0 1.0 h 0.0", "FLASER field 'logger_timestamp'"},
      // not a message at all, and a PARAM without stamps
      {"@@@ 1 2 3", "expected a message name"},
      {"PARAM name", "PARAM: expected 'PARAM name value"},
  };
}

TEST(CarmenReader, StrictModeNamesFileLineAndField) {
  const std::vector<MalformedCase> cases = MalformedCases();
  for (std::size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE(cases[i].line);
    // The malformed line is line 3, after a comment and a good line.
    const fs::path path = WriteLog("strict" + std::to_string(i),
                                   {"# header", "ODOM 0 0 0 0 0 0 0.5 h 0.0", cases[i].line});
    core::Result<CarmenLog> log = ReadCarmenLog(path, Strict());
    ASSERT_FALSE(log.ok());
    EXPECT_EQ(log.message().rfind(path.string() + ":3: ", 0), 0u) << log.message();
    EXPECT_NE(log.message().find(cases[i].field), std::string::npos) << log.message();
  }
}

TEST(CarmenReader, LenientModeSkipsAndCountsMalformedLines) {
  const std::vector<MalformedCase> cases = MalformedCases();
  std::vector<std::string> lines = {"ODOM 0 0 0 0 0 0 0.5 h 0.0"};
  for (const MalformedCase& c : cases) {
    lines.push_back(c.line);
    lines.push_back("FLASER 2 1 2 0 0 0 0 0 0 1.0 h 0.0");  // good lines survive
  }
  core::Result<CarmenLog> log = ReadCarmenLog(WriteLog("lenient", lines));  // default: lenient
  ASSERT_TRUE(log.ok()) << log.message();
  const CarmenReadSummary& s = log->summary;
  EXPECT_EQ(s.skipped_line_count, static_cast<int64_t>(cases.size()));
  ASSERT_EQ(s.skipped_lines.size(), cases.size());
  for (std::size_t i = 0; i < cases.size(); ++i) {
    EXPECT_EQ(s.skipped_lines[i].line, static_cast<int64_t>(2 + 2 * i));
    EXPECT_NE(s.skipped_lines[i].reason.find(cases[i].field), std::string::npos)
        << s.skipped_lines[i].reason;
  }
  EXPECT_EQ(log->scans.size(), cases.size());
  EXPECT_EQ(s.Count("FLASER"), static_cast<int64_t>(cases.size()));  // malformed not counted
  EXPECT_EQ(s.Count("ODOM"), 1);

  CarmenReadOptions capped;
  capped.max_recorded_skips = 2;
  core::Result<CarmenLog> few = ReadCarmenLog(WriteLog("capped", lines), capped);
  ASSERT_TRUE(few.ok()) << few.message();
  EXPECT_EQ(few->summary.skipped_line_count, static_cast<int64_t>(cases.size()));
  EXPECT_EQ(few->summary.skipped_lines.size(), 2u);
}

TEST(CarmenReader, StreamDeliversMessagesInFileOrderAndStopsOnCallbackError) {
  const fs::path path = WriteLog("stream", GoodLines());
  std::vector<int64_t> lines;
  core::Result<CarmenReadSummary> all =
      StreamCarmenLog(path, Strict(), [&lines](CarmenMessage message) {
        lines.push_back(std::visit([](const auto& m) { return m.line; }, message));
        return core::Status::Ok();
      });
  ASSERT_TRUE(all.ok()) << all.message();
  // PARAM x3, ODOM, FLASER, RLASER, RAWLASER1, ROBOTLASER1, TRUEPOS.
  EXPECT_EQ(lines, (std::vector<int64_t>{2, 3, 4, 6, 7, 9, 10, 11, 12}));

  int delivered = 0;
  core::Result<CarmenReadSummary> stopped =
      StreamCarmenLog(path, Strict(), [&delivered](CarmenMessage message) {
        ++delivered;
        if (std::holds_alternative<CarmenLaserScan>(message)) {
          return core::Status::Error("disk full");
        }
        return core::Status::Ok();
      });
  ASSERT_FALSE(stopped.ok());
  EXPECT_EQ(stopped.message(), path.string() + ":7: disk full");
  EXPECT_EQ(delivered, 5);
}

TEST(CarmenReader, InvalidOptionsAndMissingFileAreErrors) {
  CarmenReadOptions options;
  EXPECT_TRUE(options.Validate().ok());
  options.old_format_angle_increment_rad = -0.1;
  EXPECT_FALSE(options.Validate().ok());
  EXPECT_FALSE(ReadCarmenLog(WriteLog("options", GoodLines()), options).ok());
  const fs::path missing = ScratchDir("missing") / "absent.clf";
  core::Result<CarmenLog> log = ReadCarmenLog(missing);
  ASSERT_FALSE(log.ok());
  EXPECT_NE(log.message().find(missing.string()), std::string::npos);
}

TEST(CarmenTrajectory, OdometryOrLaserPoseOfSelectedLaser) {
  core::Result<CarmenLog> log = ReadCarmenLog(WriteLog("traj", GoodLines()), Strict());
  ASSERT_TRUE(log.ok()) << log.message();
  // Laser 1: FLASER (line 7) and ROBOTLASER1 (line 11); RAWLASER1 has no pose.
  core::Result<core::Trajectory> odom = CarmenScanTrajectory(*log);
  ASSERT_TRUE(odom.ok()) << odom.message();
  ASSERT_EQ(odom->size(), 2u);
  EXPECT_DOUBLE_EQ((*odom)[0].stamp_s, 10.1);
  EXPECT_TRUE((*odom)[0].pose.IsApprox(core::SE2(1.0, 2.0, 0.6)));
  EXPECT_DOUBLE_EQ((*odom)[1].stamp_s, 10.4);
  EXPECT_FALSE((*odom)[1].covariance.has_value());

  CarmenTrajectoryOptions options;
  options.pose_source = CarmenPoseSource::kLaser;
  core::Result<core::Trajectory> laser = CarmenScanTrajectory(*log, options);
  ASSERT_TRUE(laser.ok()) << laser.message();
  EXPECT_TRUE((*laser)[0].pose.IsApprox(core::SE2(1.1, 2.1, 0.6)));
  EXPECT_TRUE((*laser)[1].pose.IsApprox(core::SE2(1.22, 2.0, 0.5)));

  options.laser_id = std::nullopt;  // FLASER, RLASER, ROBOTLASER1: stamps still increase
  core::Result<core::Trajectory> every = CarmenScanTrajectory(*log, options);
  ASSERT_TRUE(every.ok()) << every.message();
  EXPECT_EQ(every->size(), 3u);
}

TEST(CarmenTrajectory, NonIncreasingStampsAreAnErrorNamingTheLines) {
  const fs::path path =
      WriteLog("stamps", {"FLASER 1 1 0 0 0 0 0 0 5.0 h 0.0", "RLASER 1 1 0 0 0 0 0 0 5.0 h 0.0",
                          "FLASER 1 1 0 0 0 0 0 0 5.0 h 0.0"});
  core::Result<CarmenLog> log = ReadCarmenLog(path, Strict());
  ASSERT_TRUE(log.ok()) << log.message();
  core::Result<core::Trajectory> trajectory = CarmenScanTrajectory(*log);
  ASSERT_FALSE(trajectory.ok());
  EXPECT_NE(trajectory.message().find("line 3"), std::string::npos) << trajectory.message();
  EXPECT_NE(trajectory.message().find("line 1"), std::string::npos) << trajectory.message();
}

}  // namespace
}  // namespace groundline::io
