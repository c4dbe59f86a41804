#include "kincal/problems/solver_contract.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>

namespace kincal::problems {
namespace {

std::string number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

bool same_cost(double a, double b) {
  if (a == b) return true;  // infinities included
  return std::abs(a - b) <= kCostSlack * std::max(std::abs(a), std::abs(b));
}

bool starts_with_gradient(const std::string& message) {
  static const std::string kWord = "gradient";
  if (message.size() < kWord.size()) return false;
  for (std::size_t i = 0; i < kWord.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(message[i])) != kWord[i]) return false;
  return true;
}

}  // namespace

std::string ContractCheck::report() const {
  std::string out;
  for (const auto& violation : violations) out += (out.empty() ? "" : "; ") + violation;
  return out;
}

ContractCheck check_contract(const LeastSquaresProblem& problem, const VectorXd& start,
                             const VectorXd& x, const Summary& summary,
                             const SolverOptions& options, const RecordingProblem* evaluations) {
  ContractCheck check;
  auto violate = [&](std::string what) { check.violations.push_back(std::move(what)); };
  const bool bounded = options.lower_bounds && options.upper_bounds;
  // Backends start from the start projected onto the box.
  VectorXd x0 = start;
  if (bounded) x0 = x0.cwiseMax(*options.lower_bounds).cwiseMin(*options.upper_bounds);

  VectorXd r;
  MatrixXd J;
  check.start_computable = x0.allFinite() && problem.evaluate(x0, &r, &J);
  // 0. A start whose residuals or Jacobian have a non-finite entry is no start either: no step
  // can be computed from it and no test can hold there.
  check.start_finite = check.start_computable && r.allFinite() && J.allFinite();
  check.start_cost =
      check.start_finite ? 0.5 * r.squaredNorm() : std::numeric_limits<double>::infinity();
  if (!check.start_finite) {
    // Nothing could be done: the backend must say so and leave x alone.
    const std::string what = check.start_computable
                                 ? "the residuals or Jacobian at the start are not finite"
                                 : "the start is not computable";
    if (summary.termination != TerminationType::kFailed)
      violate(what + ", yet the termination is " + to_string(summary.termination));
    if (x != start && x != x0) violate(what + ", yet x was changed");
    if (check.start_computable && summary.message.find("non-finite") == std::string::npos)
      violate(what + ", yet the message does not say so: '" + summary.message.substr(0, 80) + "'");
    check.cost_at_x = check.start_cost;
    return check;
  }

  // 1. A computable, finite point (inside the box, when there is one).
  if (!x.allFinite()) {
    violate("the returned x is not finite");
    check.cost_at_x = std::numeric_limits<double>::infinity();
    return check;
  }
  std::string why;
  if (!problem.evaluate(x, &r, &J, &why)) {
    violate("the residuals cannot be computed at the returned x: " + why);
    check.cost_at_x = std::numeric_limits<double>::infinity();
    return check;
  }
  if (!r.allFinite()) {
    violate("the residuals at the returned x are not finite");
    check.cost_at_x = std::numeric_limits<double>::infinity();
    return check;
  }
  if (bounded && ((x.array() < options.lower_bounds->array()).any() ||
                  (x.array() > options.upper_bounds->array()).any()))
    violate("the returned x lies outside the bounds");
  check.cost_at_x = 0.5 * r.squaredNorm();
  check.at_x = measure_stationarity(x, r, J, options);

  // 2. Never costlier than the start, nor than any point evaluated, by more than the cost's
  // rounding error at x (two costs closer than that cannot be told apart).
  const double noise = check.at_x.cost_rounding;
  if (check.cost_at_x > check.start_cost * (1 + kCostSlack) + noise)
    violate("the returned x costs " + number(check.cost_at_x) + ", more than the start (" +
            number(check.start_cost) + ")");
  check.best_evaluated_cost = check.cost_at_x;
  if (evaluations) {
    check.best_evaluated_cost = std::min(check.cost_at_x, evaluations->best_cost());
    if (check.cost_at_x > evaluations->best_cost() * (1 + kCostSlack) + noise)
      violate("the returned x costs " + number(check.cost_at_x) +
              ", but the backend evaluated a point that costs " + number(evaluations->best_cost()));
  }

  // 3. The reported costs are the true ones.
  if (!same_cost(summary.final_cost, check.cost_at_x) &&
      !(std::abs(summary.final_cost - check.cost_at_x) <= noise))
    violate("final_cost " + number(summary.final_cost) + " is not the cost at x, " +
            number(check.cost_at_x));
  if (!same_cost(summary.initial_cost, check.start_cost))
    violate("initial_cost " + number(summary.initial_cost) + " is not the cost at the start, " +
            number(check.start_cost));

  // 4. and 5. A convergence claim holds at x, and names a plateau.
  if (summary.converged()) {
    const Stationarity& s = check.at_x;
    const std::string measures = "relative gradient " + number(s.relative_gradient) + ", " +
                                 (s.gauss_newton_trusted ? "Gauss-Newton" : "steepest-descent") +
                                 " predicted relative decrease " +
                                 number(s.predicted_relative_decrease) + ", relative step " +
                                 number(s.relative_step);
    if (!s.finite) {
      violate("converged at a point whose Jacobian has a non-finite entry");
    } else if (s.on_plateau()) {
      violate("converged on a plateau: no free parameter affects the residuals at x");
    } else if (starts_with_gradient(summary.message)) {
      if (!s.gradient_test(options))
        violate("claims the gradient test, which fails at x (" + measures + " > " +
                number(options.gradient_tolerance) + ")");
    } else if (!s.gradient_test(options) && !s.cost_test(options) && !s.step_test(options)) {
      violate("claims convergence ('" + summary.message.substr(0, 60) +
              "'), but x passes none of the three tests (" + measures + ")");
    }
    if (!s.dead_parameters.empty() && summary.message.find("plateau") == std::string::npos)
      violate("converged with parameters " +
              describe_parameters(s.dead_parameters, problem.parameter_names()) +
              " that no longer affect the residuals, but the message does not name the plateau");
  }
  return check;
}

CheckedSolve solve_and_check(const Solver& solver, const LeastSquaresProblem& problem,
                             const VectorXd& start, const SolverOptions& options) {
  RecordingProblem recording(problem);
  CheckedSolve out;
  out.x = start;
  out.summary = solver.solve(recording, out.x, options);
  out.contract = check_contract(problem, start, out.x, out.summary, options, &recording);
  return out;
}

}  // namespace kincal::problems
