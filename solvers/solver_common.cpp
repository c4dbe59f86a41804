#include "kincal/solvers/solver_common.hpp"

#include <cctype>

namespace kincal::detail {
namespace {

std::string format(const char* pattern, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, pattern, value);
  return buffer;
}

// The three measures, for messages.
std::string measures(const Stationarity& s) {
  return "max|J^T r| " + format("%.3g", s.gradient_norm) + ", " +
         (s.gauss_newton_trusted ? "Gauss-Newton" : "steepest-descent") +
         " predicted relative decrease " + format("%.3g", s.predicted_relative_decrease) +
         ", relative step " + format("%.3g", s.relative_step);
}

std::string plateau_note(const Stationarity& s, const std::vector<std::string>& names) {
  return "; on a plateau in " + describe_parameters(s.dead_parameters, names) +
         ": they no longer affect the residuals (zero Jacobian columns: the model saturated, the "
         "parameters ran off towards an asymptote, or the residuals never depend on them)";
}

// The first of the three tests that x passes, named as the messages name them.
std::string passing_test(const Stationarity& s, const SolverOptions& options) {
  if (s.gradient_test(options)) return "gradient max-norm below tolerance";
  if (s.cost_test(options)) return "relative cost change below tolerance";
  if (s.step_test(options)) return "relative step below tolerance";
  return "";
}

}  // namespace

bool claims_gradient_test(const std::string& message) {
  static const std::string kWord = "gradient";
  if (message.size() < kWord.size()) return false;
  for (std::size_t i = 0; i < kWord.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(message[i])) != kWord[i]) return false;
  return true;
}

Verdict judge_convergence(const Stationarity& at_x, const SolverOptions& options,
                          const std::string& message, const std::vector<std::string>& names,
                          bool near_uncomputable) {
  if (at_x.on_plateau())
    return {TerminationType::kFailed,
            "stopped on a plateau: no parameter affects the residuals here (every Jacobian "
            "column vanished: the model saturated), so the vanishing gradient says nothing about "
            "a minimum (" +
                message + ")"};
  const std::string note = at_x.dead_parameters.empty() ? "" : plateau_note(at_x, names);
  if (at_x.claim_holds(options, claims_gradient_test(message)))
    return {TerminationType::kConverged, message + note};
  const std::string other = passing_test(at_x, options);
  if (!other.empty())
    return {TerminationType::kConverged, other + " at the returned point (" + measures(at_x) +
                                             "; the backend: " + message + ")" + note};
  if (near_uncomputable)
    return {TerminationType::kDiverged,
            "stopped at the edge of the region where residuals can be computed (" + message +
                "; the returned point is not stationary: " + measures(at_x) + ")" + note};
  return {TerminationType::kFailed, "stalled: " + message +
                                        ", but the returned point is not stationary (" +
                                        measures(at_x) + ")" + note};
}

Verdict judge_other_stop(const Stationarity& at_x, const SolverOptions& options,
                         TerminationType type, const std::string& message,
                         const std::vector<std::string>& names) {
  const std::string test = passing_test(at_x, options);
  if (test.empty() || at_x.on_plateau()) return {type, message};
  const std::string note = at_x.dead_parameters.empty() ? "" : plateau_note(at_x, names);
  return {TerminationType::kConverged, test + " at the returned point (" + measures(at_x) +
                                           "; the backend: " + message + ")" + note};
}

}  // namespace kincal::detail
