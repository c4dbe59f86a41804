#include "kincal/problems/suite_runner.hpp"

#include <algorithm>
#include <chrono>

#include "kincal/framework/least_squares/solver_registry.hpp"

namespace kincal::problems {

SolverOptions suite_options(const std::string& solver, int num_parameters) {
  SolverOptions options;
  if (solver.rfind("nlopt", 0) == 0)
    options.max_iterations = kNloptEvaluationsPerParameter * (num_parameters + 1);
  return options;
}

std::vector<SuiteCaseResult> run_suite(
    const std::string& solver, const std::vector<std::shared_ptr<const TestProblem>>& problems,
    const std::function<void(SolverOptions&)>& configure) {
  const auto backend = SolverRegistry::global().create(solver);
  std::vector<SuiteCaseResult> results;
  for (const auto& problem : problems) {
    for (const SuiteStart& start : suite_starts(*problem)) {
      SuiteCaseResult result;
      result.solver = solver;
      result.problem = problem->name();
      result.start = start.label;
      result.num_parameters = problem->num_parameters();
      result.published_minimum = problem->published_minimum();
      result.evaluable = start.evaluable;
      result.why_not_evaluable = start.why_not_evaluable;
      result.x = start.x;
      if (start.evaluable) {
        SolverOptions options = suite_options(solver, problem->num_parameters());
        if (configure) configure(options);
        const auto begin = std::chrono::steady_clock::now();
        CheckedSolve run = solve_and_check(*backend, *problem, start.x, options);
        result.seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
        result.summary = std::move(run.summary);
        result.x = std::move(run.x);
        result.contract = std::move(run.contract);
        result.outcome = classify(*problem, result.contract.cost_at_x);
      }
      results.push_back(std::move(result));
    }
  }
  return results;
}

SuiteTally tally(const std::vector<SuiteCaseResult>& results) {
  SuiteTally t;
  std::vector<double> seconds;
  for (const auto& r : results) {
    if (!r.evaluable) continue;
    ++t.cases;
    t.solved += r.outcome == Outcome::kPublishedMinimum;
    t.published_local += r.outcome == Outcome::kPublishedLocal;
    t.converged += r.summary.converged();
    t.violations += !r.contract.ok();
    bool false_claim = false;
    for (const auto& v : r.contract.violations)
      false_claim = false_claim || v.rfind("claims", 0) == 0 || v.rfind("converged", 0) == 0;
    t.false_claims += false_claim;
    seconds.push_back(r.seconds);
  }
  if (!seconds.empty()) {
    std::sort(seconds.begin(), seconds.end());
    const std::size_t mid = seconds.size() / 2;
    t.median_seconds = seconds.size() % 2 ? seconds[mid] : 0.5 * (seconds[mid - 1] + seconds[mid]);
  }
  return t;
}

}  // namespace kincal::problems
