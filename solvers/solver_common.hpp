#pragma once
// Bookkeeping shared by our own Eigen backends (gn, lm): timing, trace, callback, verbose
// lines, and the convergence tests. Backend-internal: not part of the public API.

#include <chrono>
#include <cmath>
#include <cstdio>

#include "kincal/framework/solver.hpp"

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

}  // namespace kincal::detail
