#include "groundline/core/trajectory_covariance_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "groundline/core/trajectory_io.h"

namespace groundline::core {
namespace {

namespace fs = std::filesystem;

fs::path TempFile(const std::string& name) {
  return fs::path(::testing::TempDir()) / ("trajectory_covariance_io_" + name);
}

TEST(TrajectoryCovarianceIoTest, RoundTripsThroughTheTumStamps) {
  Trajectory t;
  Matrix3 c;
  c << 4e-6, 1e-7, -2e-8, 1e-7, 9e-6, 3e-8, -2e-8, 3e-8, 1e-6;
  t.push_back({10.123456789, SE2(1.0, 2.0, 0.3), c});
  t.push_back({10.5, SE2(1.5, 2.0, 0.3), std::nullopt});
  t.push_back({11.25, SE2(2.0, 2.0, 0.3), Matrix3(c * 2.0)});
  const fs::path tum = TempFile("a.tum"), cov = TempFile("a.txt");
  ASSERT_TRUE(WriteTumTrajectory(tum, t).ok());
  ASSERT_TRUE(WriteTrajectoryCovariances(cov, t).ok());
  Result<Trajectory> read = ReadTumTrajectory(tum);
  ASSERT_TRUE(read.ok()) << read.message();
  ASSERT_TRUE(AttachTrajectoryCovariances(cov, &*read).ok());
  ASSERT_TRUE((*read)[0].covariance.has_value());
  EXPECT_TRUE((*read)[0].covariance->isApprox(c, 1e-8));
  EXPECT_FALSE((*read)[1].covariance.has_value());
  EXPECT_TRUE((*read)[2].covariance->isApprox(2.0 * c, 1e-8));
}

TEST(TrajectoryCovarianceIoTest, NamesTheLineOfAStampWithoutPose) {
  Trajectory t = {{1.0, SE2(), std::nullopt}};
  const fs::path cov = TempFile("b.txt");
  std::ofstream(cov) << "# header\n1.0 1 0 0 1 0 1\n2.0 1 0 0 1 0 1\n";
  const Status s = AttachTrajectoryCovariances(cov, &t);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find(":3"), std::string::npos) << s.message();
  std::ofstream(cov) << "1.0 1 0 0 x 0 1\n";
  const Status bad = AttachTrajectoryCovariances(cov, &t);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("c_yy"), std::string::npos) << bad.message();
}

}  // namespace
}  // namespace groundline::core
