// The mrcal problem of an intrinsic calibration (one camera at the reference,
// one board pose per view, mrcal's board flex), as intrinsic_calibration.cc
// builds and solves it, and as calibration_covariance.cc evaluates its
// Jacobian at the optimum. Private to the calibration module.
#ifndef GROUNDLINE_CALIBRATION_SRC_MRCAL_PROBLEM_H_
#define GROUNDLINE_CALIBRATION_SRC_MRCAL_PROBLEM_H_

#include <vector>

#include "groundline/calibration/calib_target.h"
#include "groundline/calibration/intrinsic_calibration.h"
#include "groundline/core/status.h"
#include "mrcal_adapter.h"

namespace groundline::calibration::internal {

struct MrcalProblem {
  mrcal_lensmodel_t lensmodel{};
  std::vector<double> intrinsics;
  std::vector<mrcal_pose_t> frames;  // rt_cam_board of each view (mrcal's frames_toref)
  // Nviews * H * W observations (x, y, weight); weight < 0: outlier or not seen.
  std::vector<mrcal_point3_t> pool;
  mrcal_calobject_warp_t warp{};
  int imagersize[2] = {0, 0};
  mrcal_problem_selections_t selections{};
};

// mrcal_optimize on the problem as it stands (seed in, solution out; new
// outliers marked in pool). *x receives the measurement vector.
mrcal_stats_t SolveMrcalProblem(MrcalProblem* problem, const BoardGrid& grid,
                                std::vector<double>* x, bool verbose);

// The covariance of the state at the optimum (intrinsic_calibration.h,
// CalibrationCovariance), from mrcal_optimizer_callback's Jacobian. Fails
// when mrcal cannot evaluate the problem or J'J is singular.
core::Result<CalibrationCovariance> ComputeCalibrationCovariance(const MrcalProblem& problem,
                                                                 const BoardGrid& grid);

}  // namespace groundline::calibration::internal

#endif  // GROUNDLINE_CALIBRATION_SRC_MRCAL_PROBLEM_H_
