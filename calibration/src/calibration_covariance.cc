// The state covariance of an intrinsic calibration from mrcal's own Jacobian
// (mrcal_problem.h). mrcal_optimizer_callback evaluates the problem at the
// solution and returns J' in CHOLMOD's compressed-column form, in the
// solver's scaled ("packed") state b* = inv(D) b. The state is small (a few
// hundred at most), so J'J is formed and inverted densely.
#include <Eigen/Cholesky>
#include <cmath>

// Only the cholmod_sparse struct layout is needed (mrcal fills it); nothing
// of CHOLMOD is called.
#include <suitesparse/cholmod.h>

#include "mrcal_problem.h"

extern "C" {
// Declared in Debian's mrcal-internal.h (libmrcal 2.2 exports it): the exact
// number of non-zeros mrcal_optimizer_callback writes into J'.
int _mrcal_num_j_nonzero(int Nobservations_board, int Nobservations_point,
                         int calibration_object_width_n, int calibration_object_height_n,
                         int Ncameras_intrinsics, int Ncameras_extrinsics, int Nframes, int Npoints,
                         int Npoints_fixed, const mrcal_observation_board_t* observations_board,
                         const mrcal_observation_point_t* observations_point,
                         mrcal_problem_selections_t problem_selections,
                         const mrcal_lensmodel_t* lensmodel);
}

namespace groundline::calibration::internal {

core::Result<CalibrationCovariance> ComputeCalibrationCovariance(const MrcalProblem& p,
                                                                 const BoardGrid& grid) {
  const int n_views = static_cast<int>(p.frames.size());
  std::vector<mrcal_observation_board_t> observations(n_views);
  for (int i = 0; i < n_views; ++i) observations[i] = {{0, -1}, i};
  const mrcal_problem_selections_t& sel = p.selections;
  const int n_state = mrcal_num_states(1, 0, n_views, 0, 0, n_views, sel, &p.lensmodel);
  const int n_meas = mrcal_num_measurements(n_views, 0, grid.width_n, grid.height_n, 1, 0, n_views,
                                            0, 0, sel, &p.lensmodel);
  const int n_obs = mrcal_num_measurements_boards(n_views, grid.width_n, grid.height_n);
  const int nnz = _mrcal_num_j_nonzero(n_views, 0, grid.width_n, grid.height_n, 1, 0, n_views, 0, 0,
                                       observations.data(), nullptr, sel, &p.lensmodel);
  std::vector<double> b_packed(n_state), x(n_meas), jx(nnz);
  std::vector<int> jp(n_meas + 1), ji(nnz);
  cholmod_sparse Jt{};
  Jt.nrow = n_state;
  Jt.ncol = n_meas;
  Jt.nzmax = nnz;
  Jt.p = jp.data();
  Jt.i = ji.data();
  Jt.x = jx.data();
  Jt.stype = 0;
  Jt.itype = CHOLMOD_INT;
  Jt.xtype = CHOLMOD_REAL;
  Jt.dtype = CHOLMOD_DOUBLE;
  Jt.sorted = 1;
  Jt.packed = 1;
  const mrcal_problem_constants_t constants = {-1.0, -1.0};
  if (!mrcal_optimizer_callback(b_packed.data(), n_state * static_cast<int>(sizeof(double)),
                                x.data(), n_meas * static_cast<int>(sizeof(double)), &Jt,
                                p.intrinsics.data(), nullptr, p.frames.data(), nullptr, &p.warp, 1,
                                0, n_views, 0, 0, observations.data(), nullptr, n_views, 0,
                                p.pool.data(), &p.lensmodel, p.imagersize, sel, &constants,
                                grid.pitch_m, grid.width_n, grid.height_n, false)) {
    return core::Status::Error("mrcal could not evaluate the solved problem's Jacobian");
  }
  // J (n_meas x n_state, packed state) from the columns of J'.
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(n_meas, n_state);
  for (int m = 0; m < n_meas; ++m) {
    for (int k = jp[m]; k < jp[m + 1]; ++k) J(m, ji[k]) = jx[k];
  }
  const Eigen::MatrixXd JtJ = J.transpose() * J;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(JtJ);
  const double max_diag = JtJ.diagonal().maxCoeff();
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-12 * max_diag)) {
    return core::Status::Error(
        "J'J of the solve is singular: the views do not constrain every parameter");
  }
  const Eigen::MatrixXd inv_JtJ = ldlt.solve(Eigen::MatrixXd::Identity(n_state, n_state));
  const Eigen::MatrixXd J_obs = J.topRows(n_obs);
  const Eigen::MatrixXd var_packed = inv_JtJ * (J_obs.transpose() * J_obs) * inv_JtJ;

  // D: unpacking a vector of ones gives the scale of every state element.
  std::vector<double> d(n_state, 1.0);
  mrcal_unpack_solver_state_vector(d.data(), 1, 0, n_views, 0, 0, sel, &p.lensmodel);
  const Eigen::Map<const Eigen::VectorXd> D(d.data(), n_state);

  // sigma: population std of the inlier residual coordinates, as mrcal.
  double sum = 0.0, sum_sq = 0.0;
  int count = 0;
  for (std::size_t k = 0; k < p.pool.size(); ++k) {
    if (p.pool[k].z < 0.0) continue;
    for (int c = 0; c < 2; ++c) {
      const double r = x[2 * k + c];
      sum += r;
      sum_sq += r * r;
      ++count;
    }
  }
  if (count < 2) return core::Status::Error("too few inlier corners for a covariance");
  const double mean = sum / count;
  CalibrationCovariance out;
  out.observed_pixel_sigma_px = std::sqrt(std::max(0.0, sum_sq / count - mean * mean));
  out.covariance = out.observed_pixel_sigma_px * out.observed_pixel_sigma_px *
                   (D.asDiagonal() * var_packed * D.asDiagonal());
  out.state_index_intrinsics =
      mrcal_state_index_intrinsics(0, 1, 0, n_views, 0, 0, n_views, sel, &p.lensmodel);
  out.state_index_frames =
      mrcal_state_index_frames(0, 1, 0, n_views, 0, 0, n_views, sel, &p.lensmodel);
  out.state_index_warp =
      sel.do_optimize_calobject_warp
          ? mrcal_state_index_calobject_warp(1, 0, n_views, 0, 0, n_views, sel, &p.lensmodel)
          : -1;
  return out;
}

}  // namespace groundline::calibration::internal
