#pragma once
// The honesty contract every backend owes its caller (docs/solvers.md, "The honesty
// contract"), checked from the outside: everything is recomputed at the point the backend
// returned, independently of what its Summary claims.
//
//  0. a start whose residuals cannot be computed, or whose residuals or Jacobian have a
//     non-finite entry, ends `failed` with x untouched (and, for a non-finite entry, a message
//     that says "non-finite");
//  1. x is finite and the residuals can be computed there, finite (unless the start could not
//     be);
//  2. x costs no more than the start, and no more than any point the backend evaluated, to
//     within the cost's rounding error at x (framework/least_squares/stationarity.hpp,
//     cost_rounding) and kCostSlack relative (the same sums in another order);
//  3. final_cost is the cost at x (to kCostSlack, or to the cost's rounding error at x: a
//     backend's evaluation may start forward kinematics elsewhere, lm's from its last poses,
//     and end a few ulp of the lengths away), initial_cost the cost at the start;
//  4. `converged` only where the test the message names holds at x, whose Jacobian must be
//     finite: a message starting with "gradient" needs every live parameter's
//     |P(J^T r)_j| <= gradient_tolerance |J_j| |r| (+ its rounding bound) at x; any
//     other claim (relative step, relative cost change, ...) is about the last step, which the
//     checker cannot repeat, and needs x to pass one of the three tests of
//     framework/least_squares/stationarity.hpp: gradient, the relative decrease the Gauss-Newton
//     model still promises <= function_tolerance, or the length of its step <= parameter_tolerance;
//  5. never `converged` on a plateau (no free parameter affects the residuals at x), and a
//     `converged` with some such parameters says "plateau" in its message.

#include <string>
#include <vector>

#include "kincal/framework/least_squares/solver.hpp"
#include "kincal/framework/least_squares/stationarity.hpp"
#include "kincal/problems/recording_problem.hpp"

namespace kincal::problems {

constexpr double kCostSlack = 1e-12;

struct ContractCheck {
  std::vector<std::string> violations;  ///< empty when the backend kept the contract
  bool start_computable = true;
  bool start_finite = true;        ///< computable, with finite residuals and Jacobian
  double start_cost = 0;           ///< recomputed
  double cost_at_x = 0;            ///< recomputed; +inf when not computable
  double best_evaluated_cost = 0;  ///< lowest cost among the points the backend evaluated
  Stationarity at_x;               ///< recomputed at x
  bool ok() const { return violations.empty(); }
  /// The violations joined by "; " ("" when none).
  std::string report() const;
};

/// Checks a finished solve: `x` returned from `start` with `summary`, under `options`.
/// `evaluations`, when given, is the RecordingProblem the backend solved through.
ContractCheck check_contract(const LeastSquaresProblem& problem, const VectorXd& start,
                             const VectorXd& x, const Summary& summary,
                             const SolverOptions& options,
                             const RecordingProblem* evaluations = nullptr);

/// A solve through a RecordingProblem, then check_contract.
struct CheckedSolve {
  Summary summary;
  VectorXd x;
  ContractCheck contract;
};
CheckedSolve solve_and_check(const Solver& solver, const LeastSquaresProblem& problem,
                             const VectorXd& start, const SolverOptions& options);

}  // namespace kincal::problems
