#pragma once
// Fits of a subset of the free parameters and K-fold cross-validation from the calibration
// data alone: each configuration is predicted by a model fitted without it.

#include <memory>
#include <string>
#include <vector>

#include "kincal/framework/calibration/calibration_problem.hpp"
#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

/// A least-squares fit of the parameters `free` (full-vector indices) from `start` (full
/// vector), with the model's prior (prior_std) when `with_prior`.
struct Fit {
  VectorXd values;  ///< full parameter vector at the solution (start where the fit failed)
  Summary summary;
  /// The solver converged or stopped at its iteration limit.
  bool ok() const {
    return summary.termination == TerminationType::kConverged ||
           summary.termination == TerminationType::kMaxIterations;
  }
};
Fit fit_parameters(std::shared_ptr<const MeasurementModel> model, const Measurements& data,
                   const VectorXd& start, const std::vector<int>& free, const Solver& solver,
                   const SolverOptions& options, bool with_prior = false);

/// K-fold cross-validation: configuration r belongs to fold r mod K (interleaved, so that
/// every fold spreads over the data as measured, and deterministic); for each fold the free
/// parameters are fitted from `start` on the other folds and the fold's readings predicted.
struct CrossValidation {
  int folds = 0;
  /// configurations x readings: held-out predicted - measured in the readings' units (NaN
  /// where missing, or where the fold's fit failed).
  MatrixXd residuals;
  int failed_folds = 0;  ///< fits that did not converge (their rows stay NaN)
  std::string failure;   ///< the first failure's message
};
/// Throws std::invalid_argument unless 2 <= folds <= configurations.
CrossValidation cross_validate(std::shared_ptr<const MeasurementModel> model,
                               const Measurements& data, const VectorXd& start,
                               const std::vector<int>& free, int folds, const Solver& solver,
                               const SolverOptions& options, bool with_prior = false);

}  // namespace kincal
