#pragma once
// The minimum of a calibration's cost resolved to rounding, for checks that compare two
// solvers' or formulations' answers (tests/solvers/implicit_formulation_test.cpp,
// benchmarks/implicit_agreement.cpp): Newton's method on the nested cost with the full Hessian.
//
// Why not the solvers' end points: their stopping tests compare costs, and in the flat valley
// of a noisy one-gauge case (cond(J) ~ 1e5) the cost stops changing by more than its rounding
// up to ~4e-4 mm from the minimum. Why not Gauss-Newton steps: the Hessian's curvature term
// sum_i r_i d2r_i/dx2, which Gauss-Newton drops, is as large as J^T J in those flat directions,
// and its steps then need not converge (case 4: they raise the cost). Newton's steps converge,
// to the point where the gradient's rounding is all that is left: ~1e-8 mm on the paper's cases.

#include <Eigen/Cholesky>
#include <limits>

#include "kincal/framework/calibration/calibration_problem.hpp"

namespace kincal::testing {

/// Newton steps on problem's cost from `x` (within ~1e-3 of its minimum): the Hessian
/// J^T J + sum_i r_i d2r_i/dx2 is formed once at `x`, its curvature term column by column from
/// central differences of the analytic Jacobian, (dJ/dx_j)^T r, and the steps go on while they
/// shrink (the gradient's norm is no test: its stiff components reach their rounding long
/// before its flat one). `last_step` gets the max-norm of the last step taken, infinity when
/// none was (the residuals could not be computed).
inline VectorXd newton_polished(const CalibrationProblem& problem, VectorXd x,
                                double* last_step = nullptr) {
  const int n = static_cast<int>(x.size());
  VectorXd r, r_plus, r_minus;
  MatrixXd J, J_plus, J_minus;
  double taken = std::numeric_limits<double>::infinity();
  if (last_step) *last_step = taken;
  if (!problem.evaluate(x, &r, &J)) return x;
  MatrixXd H = J.transpose() * J;
  for (int j = 0; j < n; ++j) {
    // In the parameters' units (mm, rad): the Jacobian's rounding over h and the third
    // derivatives times h^2 both stay far below the smallest eigenvalue of J^T J (~1e-8).
    constexpr double h = 1e-3;
    VectorXd x_plus = x, x_minus = x;
    x_plus[j] += h;
    x_minus[j] -= h;
    if (!problem.evaluate(x_plus, &r_plus, &J_plus) ||
        !problem.evaluate(x_minus, &r_minus, &J_minus))
      return x;
    H.col(j) += ((J_plus - J_minus) / (2 * h)).transpose() * r;
  }
  const Eigen::LDLT<MatrixXd> ldlt((0.5 * (H + H.transpose())).eval());
  for (int it = 0; it < 10; ++it) {
    const VectorXd step = ldlt.solve(J.transpose() * r);
    const double size = step.lpNorm<Eigen::Infinity>();
    if (!(size < taken)) break;
    const VectorXd next = x - step;
    if (!problem.evaluate(next, &r, &J)) break;
    x = next;
    taken = size;
  }
  if (last_step) *last_step = taken;
  return x;
}

}  // namespace kincal::testing
