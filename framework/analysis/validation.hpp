#pragma once
// Held-out validation of a calibrated model: the residuals of readings that took no part in
// the calibration, against what the calibration predicts for them,
//   r = predicted - measured,   cov(r) = C = diag(noise^2) + J Sigma J^T,
// noise = the readings' noise std (reading_std, or sigma_hat from the calibration) and
// Sigma = the covariance of the estimated parameters (the report's std and correlation; zero
// when not given). When the model and its uncertainty are right, chi^2 = r^T C^-1 r follows a
// chi-square distribution with m degrees of freedom (m held-out readings). The parameter
// errors are common to every configuration, so C is not diagonal: the test uses all of it.

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "kincal/framework/base/statistics.hpp"
#include "kincal/framework/calibration/calibration_problem.hpp"

namespace kincal {

struct ValidationInput {
  /// Noise std per reading (the model's reading order, readings' units); > 0.
  VectorXd noise_std;
  /// Parameters whose uncertainty is propagated (full-vector indices) and their
  /// covariance (their units); empty = the parameters are taken as exact.
  std::vector<int> parameters;
  MatrixXd covariance;
  /// Two-sided significance of the chi-square check.
  double significance = 0.01;
};

struct ReadingValidation {
  std::string name, unit;
  int count = 0;
  double rms = 0, max = 0;
  double noise_std = 0;
  /// sqrt(mean of the predicted variance of this reading's residuals): noise and parameters.
  double predicted_rms = 0;
  /// sqrt(mean of (J Sigma J^T)_ii) over this reading: the parameters' share alone.
  double parameter_rms = 0;
};

struct Validation {
  int configurations = 0;
  int readings = 0;    ///< held-out readings measured: m
  MatrixXd residuals;  ///< configurations x readings; NaN missing
  std::map<std::string, double> rms_by_unit, max_by_unit;
  std::vector<ReadingValidation> per_reading;
  bool parameter_uncertainty = false;  ///< Sigma was propagated
  double chi_square = 0;               ///< r^T C^-1 r
  double standardized_rms = 0;         ///< sqrt(chi^2 / m): 1 = as predicted
  double p_larger = 0;                 ///< P(chi^2 >= observed): small = larger than predicted
  double p_smaller = 0;                ///< P(chi^2 <= observed): small = smaller than predicted
  /// "consistent", "larger_than_predicted" or "smaller_than_predicted", at
  /// ValidationInput::significance split over the two tails.
  std::string verdict;
};

/// Thrown by validate_held_out when a statistic is not finite, so that no verdict is ever
/// given on NaN or infinity (a reading of 1e300 is a number, but its square overflows).
/// Locates the largest residual (the usual culprit).
struct NonFiniteValidation : std::domain_error {
  NonFiniteValidation(int configuration, int reading, double residual, const std::string& name);
  int configuration;  ///< row of the data (0-based)
  int reading;        ///< index in the model's readings
  double residual;    ///< predicted - measured there, the reading's unit
};

/// Residuals of `data` for the model with full parameter vector `values`, and the check.
/// Throws std::runtime_error naming the configuration when forward kinematics fails there
/// (the caller screens the rows first), std::invalid_argument for inconsistent input and
/// NonFiniteValidation when a statistic is not finite.
Validation validate_held_out(std::shared_ptr<const MeasurementModel> model,
                             const Measurements& data, const VectorXd& values,
                             const ValidationInput& input);

}  // namespace kincal
