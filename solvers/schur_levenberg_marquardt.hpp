#pragma once
// lm on the implicit-loop formulation (framework/calibration/implicit_calibration_problem.hpp): the
// poses are eliminated from the block-arrow normal equations configuration by configuration (a
// Schur complement in fixed-size kernels), the reduced p x p system is solved, and the pose
// steps are back-substituted. Algorithm and constraint weight: docs/theory.md; of lm's backend
// options (docs/solvers.md) it takes initial_trust_radius and max_radius_growth.

#include "kincal/framework/calibration/implicit_calibration_problem.hpp"
#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

/// Solves `problem` from the nested problem's free parameters `x` (in/out: the estimate). The
/// Summary is the nested problem's at the returned x, as every report reads it: final_cost is
/// its cost there and `converged` holds only where its stationarity test holds there
/// (framework/least_squares/stationarity.hpp); the trace holds the implicit iterations (their costs
/// equal the nested cost up to the closure residuals, held at the forward kinematics' tolerance).
/// A configuration where forward kinematics fails at the start fails the solve, as nested.
/// `trust_region` takes lm's backend options of the same names (docs/solvers.md).
struct ImplicitTrustRegion {
  double initial_radius = 1e4;  ///< lm's initial_trust_radius
  double max_growth = 10;       ///< lm's max_radius_growth
};
Summary solve_implicit_lm(const ImplicitCalibrationProblem& problem, VectorXd& x,
                          const SolverOptions& options,
                          const ImplicitTrustRegion& trust_region = {});

/// The damped Gauss-Newton step the solver takes at the joint point `x_joint` (problem's x,
/// the poses' local coordinates zero, i.e. at the reference poses), damping the parameters'
/// normal equations by diag(`damping`) and not the poses: [dparameters; dposes]. For tests.
VectorXd implicit_schur_step(const ImplicitCalibrationProblem& problem, const VectorXd& x_joint,
                             const VectorXd& damping);

}  // namespace kincal
