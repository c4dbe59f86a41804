#pragma once
// Bookkeeping shared by our own Eigen backends (gn, lm): timing, trace, callback, verbose
// lines, and the convergence tests. Backend-internal: not part of the public API.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "kincal/framework/least_squares/solver.hpp"
#include "kincal/framework/least_squares/stationarity.hpp"

namespace kincal::detail {

class SolveMonitor {
 public:
  SolveMonitor(const SolverOptions& options, Summary& summary)
      : options_(options), summary_(summary), start_(std::chrono::steady_clock::now()) {}

  double elapsed() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

  /// Appends a trace record, prints it when verbose, and asks the callback.
  /// Returns false when the callback asked to stop.
  bool record(IterationRecord record, const VectorXd& x) {
    record.seconds = elapsed();
    summary_.trace.push_back(record);
    if (options_.verbosity > 0)
      std::fprintf(stderr, "%s iter %3d  cost %.9e  |g| %.3e  |dx| %.3e  damping %.3e\n",
                   summary_.solver.c_str(), record.iteration, record.cost, record.gradient_norm,
                   record.step_norm, record.damping);
    return !options_.callback || options_.callback(record, x) == CallbackAction::kContinue;
  }

  void finish(TerminationType type, std::string message) {
    summary_.termination = type;
    summary_.message = std::move(message);
    summary_.wall_seconds = elapsed();
  }

 private:
  const SolverOptions& options_;
  Summary& summary_;
  std::chrono::steady_clock::time_point start_;
};

/// What a backend says when the gradient test fires (stationarity.hpp: every live parameter's
/// |J_j^T r| <= gradient_tolerance |J_j| |r|). Starts with "gradient", which makes it a
/// gradient claim (claims_gradient_test).
inline constexpr const char* kGradientTestMessage =
    "gradient below tolerance, relative to |J_j| |r|";

/// The factor a third-party library's objective is multiplied by (Ceres through a ScaledLoss,
/// NLopt directly, Ipopt's obj_scaling_factor) so that it sees the same problem whatever the
/// common scale of the residuals: a model's reading_std of 1e8 divides every residual by 1e8
/// and the cost by 1e16 without moving the minimum, but the libraries compare gradients,
/// damping and steps with absolute numbers (Ceres' projected gradient x - (x - g) rounds to 0
/// once g < ulp(x), and it then stops "converged"; L-BFGS stopped after 5 evaluations; issue
/// 35). 1 / sigma^2, with sigma the power of two at or below a Jacobian column norm (the
/// smallest that is not negligible, >= 1e-8 of the largest, or the largest) divided by
/// 2^headroom: that column of the scaled problem then has a norm in [2^headroom,
/// 2^(headroom + 1)). With no headroom, on problems whose columns are of order one (readings in
/// mm, unweighted: the paper's cases, the test suite) the libraries see about what they saw
/// before. A power of two, so that scaling is exact; 1 when every column vanished. `J` is the
/// (robust-corrected) Jacobian, at the start or where the scale is set again.
enum class ScaleBy { kSmallestColumn, kLargestColumn };
double objective_scale(const MatrixXd& J, ScaleBy column, int headroom = 0);

/// |dx| <= tol * (|x| + tol), Ceres' relative step test.
inline bool small_step(const VectorXd& dx, const VectorXd& x, double tol) {
  return dx.norm() <= tol * (x.norm() + tol);
}

/// |old - new| <= tol * old, Ceres' relative function test.
inline bool small_cost_change(double cost_old, double cost_new, double tol) {
  return std::abs(cost_old - cost_new) <= tol * cost_old;
}

/// The lowest-cost point a backend evaluated: every computable evaluation is offered, so that
/// the backend can return it whatever else happened (the contract: x is the best point seen).
class BestPoint {
 public:
  explicit BestPoint(int n) : x_(n) {}
  /// True when `cost` is a new best (x is then copied, without allocating).
  bool offer(const VectorXd& x, double cost) {
    if (!(cost < cost_)) return false;
    cost_ = cost;
    x_ = x;
    return true;
  }
  double cost() const { return cost_; }
  const VectorXd& x() const { return x_; }

 private:
  VectorXd x_;
  double cost_ = std::numeric_limits<double>::infinity();
};

/// What a backend reports for a stop.
struct Verdict {
  TerminationType type;
  std::string message;
};

/// Empty when every residual (and Jacobian entry, when `J` is given) is finite; otherwise the
/// first non-finite one, for a message: "residual 3 is nan", or "the Jacobian has a non-finite
/// entry (residual 3, parameter x2: inf)" with `names` naming parameters.
std::string non_finite_entry(const VectorXd& r, const MatrixXd* J,
                             const std::vector<std::string>& names);

/// Why a solve cannot start, when the residuals or Jacobian at the start have a non-finite
/// entry: "the Jacobian at the start has a non-finite entry (residual 3, parameter x2: nan)";
/// empty when all are finite. Such a start ends `failed` with this message on every backend:
/// no step can be computed from it, and no test can say anything there (issue 35: ipopt and
/// nlopt:LD_LBFGS called a NaN Jacobian at the start `converged`).
std::string non_finite_start(const VectorXd& r, const MatrixXd* J,
                             const std::vector<std::string>& names);
/// The same from non_finite_entry's words.
std::string non_finite_start(const std::string& entry);

/// Whether `message` claims the gradient test (it then has to hold at the returned point
/// itself); other claims (relative step, relative cost change, ...) are about the last step,
/// and the returned point must pass any of the three tests instead.
bool claims_gradient_test(const std::string& message);

/// The first of the three tests that `s` passes, named as the messages name them; empty when
/// none does.
std::string passing_test(const Stationarity& s, const SolverOptions& options);

/// The verdict on a convergence test that fired (`message`) at the point about to be returned,
/// whose stationarity is `at_x`: failed when its residuals or Jacobian are not finite there;
/// converged when that point passes the claimed test (see
/// claims_gradient_test), with any parameters that no longer affect the residuals named as a
/// plateau; on a plateau of every free parameter, failed (the gradient vanished because the
/// model saturated); otherwise, when trial points near the end could not be computed
/// (`near_uncomputable`), diverged as stopped at the edge of the region where residuals
/// exist, and failed as stalled if not, with the measures. `names` name parameters.
Verdict judge_convergence(const Stationarity& at_x, const SolverOptions& options,
                          const std::string& message, const std::vector<std::string>& names,
                          bool near_uncomputable = false);

/// The same for a stop that was not a convergence claim (iteration limit, library failure):
/// converged, naming the test and keeping the backend's words, when the point passes one of
/// the three tests; otherwise the given termination and message unchanged.
Verdict judge_other_stop(const Stationarity& at_x, const SolverOptions& options,
                         TerminationType type, const std::string& message,
                         const std::vector<std::string>& names);

}  // namespace kincal::detail
