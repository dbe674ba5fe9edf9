#include "groundline/core/trajectory_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <ostream>
#include <random>
#include <string>

#include "dataset_fixture.h"
#include "groundline/core/random_draws.h"
#include "test_data.h"
#include "test_units.h"

namespace groundline::core {
namespace {

using ::groundline::testing::kPi;
using ::groundline::testing::ScratchDir;
using ::groundline::testing::WriteText;

// Yaws near 0, +-pi/2 and +-pi (where the quaternion's qw vanishes), plus
// random ones from a fixed seed.
Trajectory MakeTrajectory() {
  Trajectory trajectory;
  const double yaws[] = {0.0,        1e-9,        -1e-9,      kPi / 2,     -kPi / 2,
                         kPi - 1e-9, -kPi + 1e-9, kPi - 1e-6, -kPi + 1e-6, kPi};
  double stamp_s = 10.25;
  for (double yaw : yaws) {
    StampedPose p;
    p.stamp_s = stamp_s;
    p.pose = SE2(0.5 * stamp_s, -3.0 + stamp_s, yaw);
    trajectory.push_back(p);
    stamp_s += 0.05;
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> position_m(-50.0, 50.0);
  std::uniform_real_distribution<double> angle_rad(-kPi, kPi);
  for (int i = 0; i < 20; ++i) {
    StampedPose p;
    p.stamp_s = stamp_s;
    const double angle = angle_rad(rng);  // one draw per statement, last first
    const Vector2 position = DrawVector<2>(position_m, rng);
    p.pose = SE2(position.x(), position.y(), angle);
    trajectory.push_back(p);
    stamp_s += 0.1;
  }
  return trajectory;
}

// Tolerances follow the written precision: 1e-9 s / 1e-9 m (9 decimals),
// yaw from a 12-decimal quaternion (error ~ 2e-12 rad).
void ExpectSameTrajectory(const Trajectory& expected, const Trajectory& actual) {
  ASSERT_EQ(expected.size(), actual.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    SCOPED_TRACE("pose " + std::to_string(i));
    EXPECT_NEAR(expected[i].stamp_s, actual[i].stamp_s, 1e-9);
    EXPECT_TRUE(expected[i].pose.IsApprox(actual[i].pose, 1e-9, 1e-10))
        << "expected " << expected[i].pose.Vector().transpose() << " got "
        << actual[i].pose.Vector().transpose();
  }
}

TEST(TrajectoryIo, TumRoundTripIncludingYawNearPi) {
  const std::filesystem::path path = ScratchDir("tum") / "traj.tum";
  const Trajectory trajectory = MakeTrajectory();
  ASSERT_TRUE(WriteTumTrajectory(path, trajectory).ok());
  const Result<Trajectory> read = ReadTumTrajectory(path);
  ASSERT_TRUE(read.ok()) << read.message();
  ExpectSameTrajectory(trajectory, *read);
}

TEST(TrajectoryIo, EurocRoundTripIncludingYawNearPi) {
  const std::filesystem::path path = ScratchDir("euroc") / "traj.csv";
  const Trajectory trajectory = MakeTrajectory();
  ASSERT_TRUE(WriteTrajectory(path, trajectory, TrajectoryFormat::kEuroc).ok());
  std::ifstream in(path);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("#timestamp [ns],p_RS_R_x [m]", 0), 0u) << header;
  const Result<Trajectory> read = ReadTrajectory(path);  // guessed from ".csv"
  ASSERT_TRUE(read.ok()) << read.message();
  ExpectSameTrajectory(trajectory, *read);
}

TEST(TrajectoryIo, EurocKeepsNanosecondStamps) {
  const std::filesystem::path path = ScratchDir("euroc_ns") / "data.csv";
  WriteText(path,
            "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],"
            "q_RS_y [],q_RS_z [],v_x\n"
            "1403636579758555392,1.0,2.0,0.5,1,0,0,0,9.9\n"
            "1403636579763555584,1.5,2.0,0.5,1,0,0,0,9.9\n");
  const Result<Trajectory> read = ReadEurocTrajectory(path);
  ASSERT_TRUE(read.ok()) << read.message();
  ASSERT_EQ(read->size(), 2u);
  // A double holds an epoch stamp to ~2.4e-7 s.
  EXPECT_NEAR((*read)[0].stamp_s, 1403636579.758555392, 5e-7);
  EXPECT_NEAR((*read)[1].stamp_s - (*read)[0].stamp_s, 0.005000192, 5e-7);
  EXPECT_NEAR((*read)[1].pose.x(), 1.5, 1e-12);
}

TEST(TrajectoryIo, TumReadsPureYawQuaternionOf3dPoseAndIgnoresZ) {
  const std::filesystem::path path = ScratchDir("tum3d") / "traj.txt";
  const double yaw = 2.5;
  const double qz = std::sin(0.5 * yaw), qw = std::cos(0.5 * yaw);
  WriteText(path, "# timestamp tx ty tz qx qy qz qw\n\n   # indented comment\n" +
                      std::string("1.0 4.0 -2.0 1.75 0 0 ") + std::to_string(qz) + " " +
                      std::to_string(qw) + "\n" +
                      // The same rotation as -q, and a quaternion scaled by
                      // 1.0009 (within the unit-norm tolerance).
                      "2.0 4.0 -2.0 0.0 -0 -0 " + std::to_string(-qz) + " " + std::to_string(-qw) +
                      "\n" + "3.0 0 0 0 0 0 " + std::to_string(1.0009 * qz) + " " +
                      std::to_string(1.0009 * qw) + "\n");
  const Result<Trajectory> read = ReadTumTrajectory(path);
  ASSERT_TRUE(read.ok()) << read.message();
  ASSERT_EQ(read->size(), 3u);
  // std::to_string keeps 6 decimals: yaw within ~2e-6 rad.
  EXPECT_NEAR((*read)[0].pose.x(), 4.0, 1e-12);
  EXPECT_NEAR((*read)[0].pose.y(), -2.0, 1e-12);
  for (const StampedPose& p : *read) EXPECT_NEAR(p.pose.yaw(), yaw, 3e-6) << p.stamp_s;
}

TEST(TrajectoryIo, TumProjectsTiltedQuaternionOntoYaw) {
  // Rotation = Rz(yaw) * Ry(pitch): the planar projection keeps the yaw.
  const double yaw = -1.2, pitch = 0.1;
  const double cy = std::cos(0.5 * yaw), sy = std::sin(0.5 * yaw);
  const double cp = std::cos(0.5 * pitch), sp = std::sin(0.5 * pitch);
  const double qw = cy * cp, qx = -sy * sp, qy = cy * sp, qz = sy * cp;
  const std::filesystem::path path = ScratchDir("tilt") / "traj.tum";
  char line[256];
  std::snprintf(line, sizeof(line), "0.5 1 2 3 %.15f %.15f %.15f %.15f\n", qx, qy, qz, qw);
  WriteText(path, line);
  const Result<Trajectory> read = ReadTumTrajectory(path);
  ASSERT_TRUE(read.ok()) << read.message();
  ASSERT_EQ(read->size(), 1u);
  EXPECT_NEAR((*read)[0].pose.yaw(), yaw, 1e-12);
}

struct MalformedCase {
  const char* name;
  const char* content;
  int line;
  const char* field;
  const char* got;
};

// Keeps the ctest names short: gtest_discover_tests appends the printed parameter.
void PrintTo(const MalformedCase& c, std::ostream* os) { *os << c.name; }

class TumMalformed : public ::testing::TestWithParam<MalformedCase> {};

TEST_P(TumMalformed, NamesFileLineAndField) {
  const MalformedCase& c = GetParam();
  const std::filesystem::path path = ScratchDir(c.name) / "bad.tum";
  WriteText(path, c.content);
  const Result<Trajectory> read = ReadTumTrajectory(path);
  ASSERT_FALSE(read.ok());
  const std::string expected_location = path.string() + ":" + std::to_string(c.line) + ":";
  EXPECT_NE(read.message().find(expected_location), std::string::npos) << read.message();
  EXPECT_NE(read.message().find(std::string("field '") + c.field + "'"), std::string::npos)
      << read.message();
  EXPECT_NE(read.message().find(c.got), std::string::npos) << read.message();
}

INSTANTIATE_TEST_SUITE_P(
    Cases, TumMalformed,
    ::testing::Values(
        MalformedCase{"field_count", "# c\n1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n", 3, "line",
                      "7 fields"},
        MalformedCase{"nan", "1 0 0 0 0 0 0 1\n2 0 0 0 nan 0 0 1\n", 2, "qx", "nan"},
        MalformedCase{"inf", "1 0 inf 0 0 0 0 1\n", 1, "y", "inf"},
        MalformedCase{"junk", "1 0 0 0 0 0 0 1x\n", 1, "qw", "1x"},
        MalformedCase{"non_unit", "1 0 0 0 0 0 0.5 0.5\n", 1, "quaternion", "norm 0.707"},
        MalformedCase{"decreasing", "1 0 0 0 0 0 0 1\n3 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 1\n", 3, "t",
                      "2.000000000 after 3.000000000"},
        MalformedCase{"repeated", "1 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n", 2, "t", "after"}),
    [](const ::testing::TestParamInfo<MalformedCase>& info) { return info.param.name; });

TEST(TrajectoryIo, EurocMalformedNamesFileLineAndField) {
  const std::filesystem::path dir = ScratchDir("euroc_bad");
  const std::string header = "#timestamp [ns],p_RS_R_x [m]\n";
  WriteText(dir / "a.csv", header + "1000,0,0,0,1,0,0,0\n1.5e9,0,0,0,1,0,0,0\n");
  WriteText(dir / "b.csv", header + "1000,0,nan,0,1,0,0,0\n");
  WriteText(dir / "c.csv", header + "1000,0,0,0,1,0,0\n");
  WriteText(dir / "d.csv", header + "2000,0,0,0,1,0,0,0\n1000,0,0,0,1,0,0,0\n");
  const struct {
    const char* file;
    int line;
    const char* field;
  } cases[] = {{"a.csv", 3, "timestamp [ns]"},
               {"b.csv", 2, "p_RS_R_y"},
               {"c.csv", 2, "line"},
               {"d.csv", 3, "timestamp [ns]"}};
  for (const auto& c : cases) {
    const Result<Trajectory> read = ReadEurocTrajectory(dir / c.file);
    ASSERT_FALSE(read.ok()) << c.file;
    const std::string location = (dir / c.file).string() + ":" + std::to_string(c.line) + ":";
    EXPECT_NE(read.message().find(location), std::string::npos) << read.message();
    EXPECT_NE(read.message().find(std::string("field '") + c.field + "'"), std::string::npos)
        << read.message();
  }
}

TEST(TrajectoryIo, MissingFileIsReportedByName) {
  const std::filesystem::path path = ScratchDir("missing") / "nope.tum";
  const Result<Trajectory> read = ReadTrajectory(path);
  ASSERT_FALSE(read.ok());
  EXPECT_NE(read.message().find("nope.tum"), std::string::npos) << read.message();
}

TEST(TrajectoryIo, WritersRejectInvalidTrajectoriesAndLeaveNoFile) {
  const std::filesystem::path dir = ScratchDir("reject");
  Trajectory unordered = MakeTrajectory();
  std::swap(unordered[3], unordered[4]);
  Trajectory non_finite = MakeTrajectory();
  non_finite[2].stamp_s = std::numeric_limits<double>::quiet_NaN();
  for (const Trajectory* t : {&unordered, &non_finite}) {
    EXPECT_FALSE(WriteTumTrajectory(dir / "t.tum", *t).ok());
    EXPECT_FALSE(WriteEurocTrajectory(dir / "t.csv", *t).ok());
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "t.tum"));
  EXPECT_FALSE(std::filesystem::exists(dir / "t.csv"));
  EXPECT_TRUE(std::filesystem::is_empty(dir)) << "a temporary file was left behind";
}

TEST(TrajectoryIo, GuessesFormatFromExtension) {
  EXPECT_EQ(GuessTrajectoryFormat("a/b/data.csv"), TrajectoryFormat::kEuroc);
  EXPECT_EQ(GuessTrajectoryFormat("a/b/ground_truth.tum"), TrajectoryFormat::kTum);
  EXPECT_EQ(GuessTrajectoryFormat("a/b/poses.txt"), TrajectoryFormat::kTum);
}

}  // namespace
}  // namespace groundline::core
