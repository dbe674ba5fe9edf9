// mrcal's optimization_inputs as groundline writes them
// (mrcal_optimization_inputs.h): the encodings against known vectors, and,
// when Debian's python3-mrcal is installed, mrcal itself reading the record
// back and recomputing the same residuals.
#include "groundline/calibration/mrcal_optimization_inputs.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "groundline/calibration/calibration_report.h"
#include "synthetic_views.h"
#include "test_data.h"

namespace groundline::calibration {
namespace {

TEST(MrcalOptimizationInputs, Base85AndCrc32MatchPythonAndZip) {
  // Python: base64.b85encode(b"hello") == b"Xk~0{Zv"; b"\0\0\0\0" -> b"00000".
  EXPECT_EQ(Base85Encode("hello"), "Xk~0{Zv");
  EXPECT_EQ(Base85Encode(std::string(4, '\0')), "00000");
  EXPECT_EQ(Base85Encode(""), "");
  // The CRC-32 check value of zip / IEEE 802.3.
  EXPECT_EQ(Crc32("123456789"), 0xCBF43926u);
  EXPECT_EQ(Crc32(""), 0u);
}

TEST(MrcalOptimizationInputs, MrcalReadsTheRecordAndRecomputesTheResiduals) {
  const CalibTarget target = testing::SyntheticAprilGrid();
  const BoardGrid grid = MakeBoardGrid(target);
  const std::vector<CalibrationView> views =
      testing::SyntheticViews(testing::TrueOpencv8Camera(), target, grid, 12, 0.1, 7);
  core::Result<IntrinsicCalibration> cal =
      CalibrateIntrinsics(views, grid, 640, 480, IntrinsicCalibrationOptions{});
  ASSERT_TRUE(cal.ok()) << cal.message();
  const std::string b85 = MrcalOptimizationInputsBase85(*cal);
  EXPECT_GT(b85.size(), 1000u);
  const std::filesystem::path dir = groundline::testing::ScratchDir("optimization_inputs");
  const CalibrationReport report = BuildCalibrationReport(*cal, "grid", {}, ReportThresholds{});
  ASSERT_TRUE(WriteCalibrationOutputs(dir, report, *cal).ok());
  if (std::system("/usr/bin/python3 -c 'import mrcal' > /dev/null 2>&1") != 0) {
    GTEST_SKIP() << "python3-mrcal is not installed (apt-get install python3-mrcal): mrcal's "
                    "own reading of the record is not checked";
  }
  // mrcal evaluates its problem from the record; its per-point RMS must be
  // groundline's.
  std::ofstream(dir / "check.py")
      << "import sys, numpy as np, mrcal\n"
         "m = mrcal.cameramodel(sys.argv[1])\n"
         "oi = m.optimization_inputs()\n"
         "x = mrcal.optimizer_callback(**oi, no_jacobian=True, no_factorization=True)[1]\n"
         "n = mrcal.num_measurements_boards(**oi)\n"
         "inl = np.sum(oi['observations_board'][..., 2] > 0)\n"
         "print('%.12f %d' % (np.sqrt(np.sum(x[:n]**2) / inl), len(oi['imagepaths'])))\n";
  const std::string command = "/usr/bin/python3 " + (dir / "check.py").string() + " " +
                              (dir / "camera.cameramodel").string() + " > " +
                              (dir / "out.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << std::ifstream(dir / "out.txt").rdbuf();
  std::ifstream in(dir / "out.txt");
  double rms = 0.0;
  int paths = 0;
  in >> rms >> paths;
  EXPECT_NEAR(rms, cal->summary.rms_px, 1e-9);
  EXPECT_EQ(paths, static_cast<int>(views.size()));
}

}  // namespace
}  // namespace groundline::calibration
