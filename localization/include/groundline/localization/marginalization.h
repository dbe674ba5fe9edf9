// Schur-complement marginalization as pure functions over explicit index
// sets, and the square-root prior it leaves behind (the marginal prior of a
// sliding-window smoother; cf. Basalt's marg_helper and the marginalization
// factor of VINS-Fusion).
//
// Linear system. Near a linearization point x0 the cost of a set of factors
// is, in the tangent coordinates dx of the variables (right perturbations for
// SE(2) poses, plain differences for Euclidean blocks),
//   cost(dx) ~ 0.5 ||J dx + r||^2 = 0.5 dx^T H dx + b^T dx + const,
//   H = J^T J,  b = J^T r   (b is the gradient, so the minimum is H dx = -b).
//
// Marginalizing the variables m and keeping k (Schur complement):
//   H' = H_kk - H_km H_mm^+ H_mk,   b' = b_k - H_km H_mm^+ b_m,
// with H_mm^+ the pseudo-inverse of H_mm (eigenvalues below a threshold are
// treated as unobservable directions and dropped). The square-root form
// (J', r') with J'^T J' = H', J'^T r' = b' is what Ceres consumes:
// J' = sqrt(L) V^T, r' = sqrt(L)^-1 V^T b' from H' = V L V^T.
//
// All functions are pure and thread-safe.
#ifndef GROUNDLINE_LOCALIZATION_MARGINALIZATION_H_
#define GROUNDLINE_LOCALIZATION_MARGINALIZATION_H_

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>

#include <Eigen/Core>
#include <span>
#include <vector>

#include "groundline/core/status.h"

namespace groundline::localization {

struct LinearSystem {
  Eigen::MatrixXd H;  // n x n, symmetric positive semi-definite
  Eigen::VectorXd b;  // n, the gradient J^T r
};

// The Schur complement onto `keep` (scalar indices into H, in the order of
// the result) after eliminating `marginalize`. The two sets must be disjoint
// and index into H (asserted); indices in neither are dropped (their coupling
// ignored). Fails when H is not finite.
core::Result<LinearSystem> MarginalizeSchur(const LinearSystem& system, std::span<const int> keep,
                                            std::span<const int> marginalize,
                                            double min_eigenvalue = 1e-10);

// The square-root form of a system: 0.5 ||J dx + r||^2 equals
// 0.5 dx^T H dx + b^T dx up to a constant. Directions of H with eigenvalue
// below min_eigenvalue get zero rows. Fails when H is not finite or has an
// eigenvalue below -min_eigenvalue (not PSD).
struct SqrtPrior {
  Eigen::MatrixXd J;  // n x n
  Eigen::VectorXd r;  // n
};
core::Result<SqrtPrior> SqrtPriorFromSystem(const LinearSystem& system,
                                            double min_eigenvalue = 1e-10);

// A variable of a linearization: a Ceres parameter block, either an SE(2)
// pose (3 ambient doubles x, y, yaw; tangent = right perturbation) or a
// Euclidean block of `size` doubles.
struct LinearizationVariable {
  const double* values = nullptr;  // not owned
  int size = 3;
  bool is_pose = true;
  int TangentSize() const { return size; }
};

// One factor: a cost function, an optional robust loss (not owned, may be
// null) and the indices of its parameter blocks among the variables.
struct LinearizationFactor {
  const ceres::CostFunction* cost = nullptr;
  const ceres::LossFunction* loss = nullptr;
  std::vector<int> variables;
};

// H and b of the factors at the variables' current values, in tangent
// coordinates, the variables stacked in order. A robust loss rho(s),
// s = ||r||^2, is applied by iteratively-reweighted least squares: r and J
// scaled by sqrt(rho'(s)) (the first-order part of Ceres' corrector).
// Fails when a cost function fails to evaluate or returns non-finite values.
core::Result<LinearSystem> LinearizeFactors(std::span<const LinearizationVariable> variables,
                                            std::span<const LinearizationFactor> factors);

// The prior left by marginalization: 0.5 ||r0 + J delta||^2 with
// delta_i = x_i (-) x0_i per kept variable (SE(2): Log(x0^-1 x); Euclidean:
// x - x0), stacked in order. x0 (the linearization point) and J stay fixed
// (first-estimate Jacobians).
struct MarginalPrior {
  std::vector<std::vector<double>> x0;  // ambient values per kept variable
  std::vector<bool> is_pose;            // per kept variable
  SqrtPrior sqrt_prior;
  int TangentDimension() const { return static_cast<int>(sqrt_prior.r.size()); }
};

// The Ceres factor of a MarginalPrior; parameter blocks: the kept variables
// in order. Its Jacobian is J times the exact derivative of delta (Jr^-1 for
// poses, so the Jacobians are checkable numerically), lifted to the ambient
// pose blocks as the other factors are.
class MarginalPriorFactor final : public ceres::CostFunction {
 public:
  explicit MarginalPriorFactor(MarginalPrior prior);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  const MarginalPrior& prior() const { return prior_; }

 private:
  MarginalPrior prior_;
  std::vector<int> offsets_;  // tangent offset of each variable
};

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_MARGINALIZATION_H_
