#include "kincal/framework/calibration/calibration_solve.hpp"

#include <memory>
#include <stdexcept>

#include "kincal/framework/calibration/constrained_problem.hpp"
#include "kincal/framework/calibration/implicit_calibration_problem.hpp"

namespace kincal {

const char* to_string(Formulation formulation) {
  return formulation == Formulation::kImplicit ? "implicit" : "nested";
}

Formulation parse_formulation(const std::string& text) {
  if (text == "nested") return Formulation::kNested;
  if (text == "implicit") return Formulation::kImplicit;
  throw std::invalid_argument("formulation must be nested or implicit, not '" + text + "'");
}

Formulation default_formulation(const MeasurementModel&) { return Formulation::kNested; }

namespace {

// Why `requested` cannot be solved implicitly here, or empty.
std::string implicit_obstacle(const Solver& solver, const CalibrationProblem& problem,
                              const Prior& prior, const SolverOptions& options) {
  if (!ImplicitCalibrationProblem::applicable(problem.model()))
    return problem.model().mechanism().type() + " is not a closed chain";
  if (prior.any()) return "a prior is not part of it yet";
  if (!problem.model().constraints().empty())
    return "the model's parameter-only constraints are not part of it yet";
  if (problem.num_parameters() == 0) return "there is no free parameter";
  if (!solver.solves_implicit(options))
    return "solver " + solver.name() + " does not solve it with these options";
  return {};
}

// An implicit solve worth replacing by the nested one: not a convergence, not the user's
// stop, not the iteration budget the user gave.
bool implicit_solve_failed(const Summary& summary) {
  return summary.termination == TerminationType::kFailed ||
         summary.termination == TerminationType::kDiverged;
}

// `text` without a trailing `suffix`: the implicit solver ends its messages with
// " (implicit formulation)", which the note already says.
std::string without_suffix(const std::string& text, const std::string& suffix) {
  const bool ends = text.size() >= suffix.size() &&
                    text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
  return ends ? text.substr(0, text.size() - suffix.size()) : text;
}

}  // namespace

CalibrationSolve solve_calibration(const Solver& solver, const CalibrationProblem& problem,
                                   const Prior& prior, VectorXd& x, const SolverOptions& options,
                                   Formulation requested) {
  CalibrationSolve out;
  if (requested == Formulation::kImplicit) {
    const std::string obstacle = implicit_obstacle(solver, problem, prior, options);
    if (obstacle.empty()) {
      // The problem outlives the solve: a non-owning pointer is enough.
      const ImplicitCalibrationProblem implicit(
          std::shared_ptr<const CalibrationProblem>(&problem, [](const CalibrationProblem*) {}));
      const VectorXd start = x;
      out.summary = solver.solve_implicit(implicit, x, options);
      out.formulation = Formulation::kImplicit;
      if (!implicit_solve_failed(out.summary)) return out;
      // Rare (2 of 800 far starts of the paper's cases: docs/benchmarks.md), and the nested
      // solve takes its own path from the start, so a failed implicit solve costs the user one
      // more solve rather than a calibration.
      out.note = "implicit formulation " + std::string(to_string(out.summary.termination)) +
                 " after " + std::to_string(out.summary.iterations) + " iterations (" +
                 without_suffix(out.summary.message, " (implicit formulation)") +
                 "): solved nested from the same start";
      out.failed_implicit = std::move(out.summary);
      x = start;
    } else {
      out.note = "implicit formulation not used (" + obstacle + "): solved nested";
    }
  }
  out.summary = solve_nested_calibration(solver, problem, prior, x, options);
  out.formulation = Formulation::kNested;
  return out;
}

}  // namespace kincal
