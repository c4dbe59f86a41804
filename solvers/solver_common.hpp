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

/// Whether `message` claims the gradient test (it then has to hold at the returned point
/// itself); other claims (relative step, relative cost change, ...) are about the last step,
/// and the returned point must pass any of the three tests instead.
bool claims_gradient_test(const std::string& message);

/// The verdict on a convergence test that fired (`message`) at the point about to be returned,
/// whose stationarity is `at_x`: converged when that point passes the claimed test (see
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
