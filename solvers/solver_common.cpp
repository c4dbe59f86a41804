#include "kincal/solvers/solver_common.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace kincal::detail {
namespace {

std::string format(const char* pattern, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, pattern, value);
  return buffer;
}

// The three measures, for messages.
std::string measures(const Stationarity& s) {
  return "relative gradient " + format("%.3g", s.relative_gradient) + ", " +
         (s.gauss_newton_trusted ? "Gauss-Newton" : "steepest-descent") +
         " predicted relative decrease " + format("%.3g", s.predicted_relative_decrease) +
         ", relative step " + format("%.3g", s.relative_step);
}

std::string plateau_note(const Stationarity& s, const std::vector<std::string>& names) {
  return "; on a plateau in " + describe_parameters(s.dead_parameters, names) +
         ": they no longer affect the residuals (zero Jacobian columns: the model saturated, the "
         "parameters ran off towards an asymptote, or the residuals never depend on them)";
}

std::string format_value(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", value);
  return buffer;
}

}  // namespace

double objective_scale(const MatrixXd& J, ScaleBy column, int headroom) {
  double largest = 0;
  for (Eigen::Index j = 0; j < J.cols(); ++j) largest = std::max(largest, J.col(j).norm());
  if (!(largest > 0) || !std::isfinite(largest)) return 1;
  double norm = largest;
  if (column == ScaleBy::kSmallestColumn)
    for (Eigen::Index j = 0; j < J.cols(); ++j) {
      const double c = J.col(j).norm();
      if (c >= 1e-8 * largest) norm = std::min(norm, c);
    }
  // sigma = 2^(e - headroom) with 2^e <= norm: a = 2^(2 (headroom - e)), clamped to stay a
  // normal double.
  const int exponent = std::clamp(2 * (headroom - std::ilogb(norm)), -1000, 1000);
  return std::ldexp(1.0, exponent);
}

std::string passing_test(const Stationarity& s, const SolverOptions& options) {
  if (s.gradient_test(options)) return kGradientTestMessage;
  if (s.cost_test(options)) return "relative cost change below tolerance";
  if (s.step_test(options)) return "relative step below tolerance";
  return "";
}

std::string non_finite_entry(const VectorXd& r, const MatrixXd* J,
                             const std::vector<std::string>& names) {
  for (Eigen::Index i = 0; i < r.size(); ++i)
    if (!std::isfinite(r[i]))
      return "residual " + std::to_string(i + 1) + " is " + format_value(r[i]);
  if (!J) return "";
  for (Eigen::Index j = 0; j < J->cols(); ++j)
    for (Eigen::Index i = 0; i < J->rows(); ++i)
      if (!std::isfinite((*J)(i, j)))
        return "the Jacobian has a non-finite entry (residual " + std::to_string(i + 1) +
               ", parameter " + describe_parameters({static_cast<int>(j)}, names) + ": " +
               format_value((*J)(i, j)) + ")";
  return "";
}

std::string non_finite_start(const VectorXd& r, const MatrixXd* J,
                             const std::vector<std::string>& names) {
  return non_finite_start(non_finite_entry(r, J, names));
}

std::string non_finite_start(const std::string& entry) {
  if (entry.empty()) return "";
  if (entry.rfind("residual", 0) == 0)
    return "the residuals at the start have a non-finite entry (" + entry + ")";
  return "the Jacobian at the start has a non-finite entry" +
         entry.substr(std::string("the Jacobian has a non-finite entry").size());
}

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
  if (!at_x.finite)
    return {TerminationType::kFailed,
            "the residuals or Jacobian at the returned point have a non-finite entry, so no "
            "test can hold there (" +
                message + ")"};
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
  if (test.empty() || !at_x.finite || at_x.on_plateau()) return {type, message};
  const std::string note = at_x.dead_parameters.empty() ? "" : plateau_note(at_x, names);
  return {TerminationType::kConverged, test + " at the returned point (" + measures(at_x) +
                                           "; the backend: " + message + ")" + note};
}

}  // namespace kincal::detail
