#include "kincal/framework/least_squares/solver.hpp"

#include <cstdio>
#include <sstream>

namespace kincal {

const char* to_string(TerminationType type) {
  switch (type) {
    case TerminationType::kConverged:
      return "converged";
    case TerminationType::kMaxIterations:
      return "max_iterations";
    case TerminationType::kDiverged:
      return "diverged";
    case TerminationType::kFailed:
      return "failed";
    case TerminationType::kUserStopped:
      return "user_stopped";
  }
  return "unknown";
}

std::string Summary::brief_report() const {
  char buf[256];
  std::snprintf(buf, sizeof buf, "%s: %s after %d iterations, cost %.6g -> %.6g (%.3g s)",
                solver.c_str(), to_string(termination), iterations, initial_cost, final_cost,
                wall_seconds);
  std::string out = buf;
  if (!message.empty()) out += " — " + message;
  return out;
}

Summary Solver::solve_implicit(const ImplicitCalibrationProblem&, VectorXd&,
                               const SolverOptions&) const {
  throw InvalidSolverOptions(name() + ": no implicit formulation");
}

void Solver::check_options(const SolverOptions& options) const {
  // Backend keys are checked by each backend against its own list (require_known_keys):
  // rejecting every key here broke every backend that calls the base and takes options.
  // 0 would return the start unsolved, and a caller could take it for a calibration (issue 35:
  // kincal calibrate --max-iterations 0 wrote the nominal model and exited 0).
  if (options.max_iterations < 1)
    throw InvalidSolverOptions(name() + ": max_iterations must be >= 1, not " +
                               std::to_string(options.max_iterations));
  if (options.lower_bounds.has_value() != options.upper_bounds.has_value())
    throw InvalidSolverOptions(name() + ": give both lower and upper bounds, or neither");
}

void Solver::check_sizes(const LeastSquaresProblem& problem, const VectorXd& x,
                         const SolverOptions& options) const {
  const int n = problem.num_parameters();
  if (x.size() != n)
    throw InvalidSolverOptions(name() + ": x has " + std::to_string(x.size()) +
                               " entries, the problem " + std::to_string(n) + " parameters");
  if (!options.lower_bounds || !options.upper_bounds) return;
  if (options.lower_bounds->size() != n || options.upper_bounds->size() != n)
    throw InvalidSolverOptions(name() + ": bounds must have one entry per parameter (" +
                               std::to_string(n) + ")");
  for (int i = 0; i < n; ++i)
    if (!((*options.lower_bounds)[i] <= (*options.upper_bounds)[i]))
      throw InvalidSolverOptions(name() + ": lower bound above upper bound for parameter " +
                                 std::to_string(i));
}

namespace solver_option {

void require_known_keys(const std::string& solver, const SolverOptions& options,
                        const std::vector<std::string>& known) {
  for (const auto& [key, value] : options.backend_options) {
    bool found = false;
    for (const auto& k : known) found = found || k == key;
    if (!found) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      throw InvalidSolverOptions(
          solver + ": unknown option '" + key + "'" +
          (list.empty() ? " (this solver takes no options)" : " (known: " + list + ")"));
    }
  }
}

double get_double(const std::string& solver, const SolverOptions& options, const std::string& key,
                  double fallback) {
  const auto it = options.backend_options.find(key);
  if (it == options.backend_options.end()) return fallback;
  std::istringstream in(it->second);
  double value;
  if (!(in >> value) || !(in >> std::ws).eof())
    throw InvalidSolverOptions(solver + ": option " + key + "='" + it->second +
                               "' is not a number");
  return value;
}

int get_int(const std::string& solver, const SolverOptions& options, const std::string& key,
            int fallback) {
  const auto it = options.backend_options.find(key);
  if (it == options.backend_options.end()) return fallback;
  std::istringstream in(it->second);
  int value;
  if (!(in >> value) || !(in >> std::ws).eof())
    throw InvalidSolverOptions(solver + ": option " + key + "='" + it->second +
                               "' is not an integer");
  return value;
}

std::string get_choice(const std::string& solver, const SolverOptions& options,
                       const std::string& key, const std::vector<std::string>& choices,
                       const std::string& fallback) {
  const auto it = options.backend_options.find(key);
  if (it == options.backend_options.end()) return fallback;
  for (const auto& c : choices)
    if (c == it->second) return c;
  std::string list;
  for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
  throw InvalidSolverOptions(solver + ": option " + key + "='" + it->second +
                             "' is not one of: " + list);
}

}  // namespace solver_option
}  // namespace kincal
