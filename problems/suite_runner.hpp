#pragma once
// Runs backends on the suite and tallies what they did: what `kincal solver-suite`, the
// solver-suite benchmark and the conformance tests share.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "kincal/problems/solver_contract.hpp"
#include "kincal/problems/suite.hpp"

namespace kincal::problems {

/// kincal's default SolverOptions, except for NLopt, whose iteration limit counts objective
/// evaluations: it gets kNloptEvaluationsPerParameter (n + 1) of them, about what the other
/// backends' 200 iterations give them (each a residual vector and an n-column Jacobian).
constexpr int kNloptEvaluationsPerParameter = 200;
SolverOptions suite_options(const std::string& solver, int num_parameters);

/// One backend on one start of one problem.
struct SuiteCaseResult {
  std::string solver, problem, start;
  int num_parameters = 0;
  bool evaluable = true;  ///< false: the start's cost overflows; nothing was run
  std::string why_not_evaluable;
  double published_minimum = 0;
  Summary summary;
  VectorXd x;
  ContractCheck contract;
  Outcome outcome = Outcome::kElsewhere;
  double seconds = 0;  ///< wall time of the solve
};

/// Every start of every problem in `problems` with `solver` (a registry name), in order.
/// `configure` may adjust the options of each run (it gets the defaults above).
std::vector<SuiteCaseResult> run_suite(
    const std::string& solver, const std::vector<std::shared_ptr<const TestProblem>>& problems,
    const std::function<void(SolverOptions&)>& configure = {});

/// What a table row says about one backend.
struct SuiteTally {
  int cases = 0;            ///< evaluable starts
  int solved = 0;           ///< reached the lowest published value
  int published_local = 0;  ///< reached a published local minimum instead
  int converged = 0;        ///< reported `converged`
  int false_claims = 0;     ///< `converged` reports that broke the contract (rules 4, 5)
  int violations = 0;       ///< cases with any contract violation
  double median_seconds = 0;
};
SuiteTally tally(const std::vector<SuiteCaseResult>& results);

}  // namespace kincal::problems
