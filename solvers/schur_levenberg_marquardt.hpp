#pragma once
// lm on the implicit-loop formulation (framework/calibration/implicit_calibration_problem.hpp): the
// poses are eliminated from the block-arrow normal equations configuration by configuration (a
// Schur complement in fixed-size kernels), the reduced p x p system is solved, and the pose
// steps are back-substituted. Algorithm and constraint weight: docs/theory.md; options as lm's
// (docs/solvers.md) without loss, bounds and geodesic acceleration.

#include "kincal/framework/calibration/implicit_calibration_problem.hpp"
#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

/// Solves `problem` from the nested problem's free parameters `x` (in/out: the estimate). The
/// Summary is the nested problem's at the returned x, as every report reads it: final_cost is
/// its cost there and `converged` holds only where its stationarity test holds there
/// (framework/least_squares/stationarity.hpp); the trace holds the implicit iterations (their costs
/// equal the nested cost up to the closure residuals, held at the forward kinematics' tolerance).
/// A configuration where forward kinematics fails at the start fails the solve, as nested.
Summary solve_implicit_lm(const ImplicitCalibrationProblem& problem, VectorXd& x,
                          const SolverOptions& options);

/// The damped Gauss-Newton step the solver takes at the joint point `x_joint` (problem's x,
/// the poses' local coordinates zero, i.e. at the reference poses), damping the parameters'
/// normal equations by diag(`damping`) and not the poses: [dparameters; dposes]. For tests.
VectorXd implicit_schur_step(const ImplicitCalibrationProblem& problem, const VectorXd& x_joint,
                             const VectorXd& damping);

}  // namespace kincal
