#include "kincal/framework/least_squares/solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <typeinfo>

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
  // A backend's own settings are checked by the backend (settings_for: its type, its
  // validity_error).
  // 0 would return the start unsolved, and a caller could take it for a calibration (issue 35:
  // kincal calibrate --max-iterations 0 wrote the nominal model and exited 0).
  if (options.max_iterations < 1)
    throw InvalidSolverOptions(name() + ": max_iterations must be >= 1, not " +
                               std::to_string(options.max_iterations));
  if (options.lower_bounds.has_value() != options.upper_bounds.has_value())
    throw InvalidSolverOptions(name() + ": give both lower and upper bounds, or neither");
  if (options.loss.kind != RobustLoss::Kind::kNone && !takes_robust_loss())
    throw InvalidSolverOptions(name() +
                               ": no robust loss (this solver minimises the plain sum "
                               "of squares)");
  if (options.backend) {
    // typeid of the objects: the dynamic types (settings of a backend that takes none are
    // NoBackendSettings).
    const BackendSettings& given = *options.backend;
    const std::unique_ptr<BackendSettings> own_settings = default_settings();
    const BackendSettings& own = *own_settings;
    if (typeid(given) != typeid(own))
      throw InvalidSolverOptions(name() + ": the backend settings given are another solver's");
    const std::string error = given.validity_error();
    if (!error.empty()) throw InvalidSolverOptions(name() + ": " + error);
  }
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

std::unique_ptr<BackendSettings> Solver::default_settings() const {
  return std::make_unique<NoBackendSettings>();
}

std::shared_ptr<const BackendSettings> Solver::parse_settings(
    const std::map<std::string, std::string>& text) const {
  std::unique_ptr<BackendSettings> settings = default_settings();
  try {
    for (const auto& [key, value] : text) settings->set(key, value);
  } catch (const InvalidSolverOptions& e) {
    throw InvalidSolverOptions(name() + ": " + e.what());
  }
  const std::string error = settings->validity_error();
  if (!error.empty()) throw InvalidSolverOptions(name() + ": " + error);
  return settings;
}

std::shared_ptr<const BackendSettings> Solver::settings_in_force(
    const SolverOptions& options) const {
  if (options.backend) return options.backend;
  return default_settings();
}

std::vector<std::string> changed_settings(const SolverOptions& options) {
  const SolverOptions defaults;
  std::vector<std::string> out;
  auto number = [&](const char* key, double value, double fallback) {
    if (value != fallback) out.push_back(key + (" " + backend_settings::text_of(value)));
  };
  number("max_iterations", options.max_iterations, defaults.max_iterations);
  number("function_tolerance", options.function_tolerance, defaults.function_tolerance);
  number("parameter_tolerance", options.parameter_tolerance, defaults.parameter_tolerance);
  number("gradient_tolerance", options.gradient_tolerance, defaults.gradient_tolerance);
  if (options.loss.kind != RobustLoss::Kind::kNone)
    out.push_back("loss " + options.loss.to_string());
  if (options.lower_bounds) out.push_back("bounds given");
  if (options.backend) {
    const auto given = options.backend->in_force();
    const auto fallback = options.backend->defaults()->in_force();
    for (std::size_t i = 0; i < given.size(); ++i)
      if (i >= fallback.size() || given[i] != fallback[i])
        out.push_back(given[i].first + " " + given[i].second);
  }
  return out;
}

void NoBackendSettings::set(const std::string& key, const std::string&) {
  throw InvalidSolverOptions("unknown option '" + key + "' (this solver takes no options)");
}

namespace backend_settings {

double parse_double(const std::string& key, const std::string& text,
                    const std::string& infinity_word) {
  if (!infinity_word.empty() && text == infinity_word)
    return std::numeric_limits<double>::infinity();
  std::istringstream in(text);
  double value;
  if (!(in >> value) || !(in >> std::ws).eof())
    throw InvalidSolverOptions("option " + key + "='" + text + "' is not a number");
  return value;
}

int parse_int(const std::string& key, const std::string& text) {
  std::istringstream in(text);
  int value;
  if (!(in >> value) || !(in >> std::ws).eof())
    throw InvalidSolverOptions("option " + key + "='" + text + "' is not an integer");
  return value;
}

std::string parse_choice(const std::string& key, const std::string& text,
                         const std::vector<std::string>& choices) {
  for (const auto& c : choices)
    if (c == text) return c;
  std::string list;
  for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
  throw InvalidSolverOptions("option " + key + "='" + text + "' is not one of: " + list);
}

std::string text_of(double value, const std::string& infinity_word) {
  if (!infinity_word.empty() && value == std::numeric_limits<double>::infinity())
    return infinity_word;
  char buf[32];
  int digits = 1;
  for (; digits < 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, value);
    if (std::strtod(buf, nullptr) == value || std::isnan(value)) break;
  }
  // Whole numbers below 1e15 in full ("10000", not "1e+04"): %g switches to an exponent once
  // it exceeds the precision.
  const double magnitude = std::abs(value);
  if (magnitude >= 1 && magnitude < 1e15)
    digits = std::max(digits, static_cast<int>(std::floor(std::log10(magnitude))) + 1);
  std::snprintf(buf, sizeof buf, "%.*g", digits, value);
  return buf;
}

void unknown_key(const std::string& key, const std::vector<std::string>& known) {
  std::string list;
  for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
  throw InvalidSolverOptions(
      "unknown option '" + key + "'" +
      (list.empty() ? " (this solver takes no options)" : " (known: " + list + ")"));
}

}  // namespace backend_settings
}  // namespace kincal
