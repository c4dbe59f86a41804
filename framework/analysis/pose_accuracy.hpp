#pragma once
// Predicted pose error over the workspace from a parameter covariance: how far the pose a
// model predicts for commanded actuator values is expected to be from the true one, when the
// parameters are off by an error with covariance Cov (e.g. the covariance of a calibration's
// estimate, or the spread of manufacturing errors around the nominal values).
//
// To first order a parameter error dp moves the pose by J_f dp (J_f: the free columns of
// Mechanism::pose_jacobian_params), so the pose error at configuration q has covariance
// J_f(q) Cov J_f(q)^T (6 x 6: position block mm^2, orientation block rad^2). Over workspace
// samples drawn in the model's configuration box this gives, for position and orientation:
//   1 sigma = sqrt(E|e|^2) = sqrt(trace of the 3 x 3 block) at a configuration,
//   95 %    = the 95 % quantile of |e| there (|e|^2 is a weighted sum of chi-squares; see
//             error_norm_quantile),
// each summarised by its mean and its max over the samples, plus the RMS over the workspace
// (sqrt of the mean of E|e|^2), which is what a Monte Carlo's RMS validation error estimates.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "kincal/framework/kinematics/measurement_model.hpp"

namespace kincal {

/// Configurations drawn in the workspace and the pose Jacobian w.r.t. the free parameters at
/// each.
struct WorkspaceSamples {
  MatrixXd actuators;             ///< samples x num_actuators
  std::vector<Matrix6Xd> J_free;  ///< per sample: 6 x free, the free columns of J_pose_params
};

/// Draws `count` configurations uniformly in the box home +- model.actuator_ranges() (home
/// from the model's nominal values, as a controller commands them) that forward kinematics
/// with `params` (full parameter vector) reaches, and the pose Jacobian at each (sensor
/// parameters do not move the pose: zero columns). Deterministic for a seed. Throws
/// std::runtime_error when configurations keep failing (1000 attempts per sample) and
/// std::invalid_argument when the home pose is unreachable.
WorkspaceSamples sample_workspace(const MeasurementModel& model, const VectorXd& params,
                                  const std::vector<int>& free_indices, int count,
                                  std::uint64_t seed);

/// Predicted pose error over the samples (see the file comment). Position in mm,
/// orientation in rad (|dw|: to first order the paper's Euler-angle norm).
struct PoseErrorPrediction {
  int samples = 0;
  double position_rms = 0;  ///< sqrt(mean over samples of E|e_p|^2)
  double position_mean_1sigma = 0, position_max_1sigma = 0;
  double position_mean_95 = 0, position_max_95 = 0;
  double orientation_rms = 0;
  double orientation_mean_1sigma = 0, orientation_max_1sigma = 0;
  double orientation_mean_95 = 0, orientation_max_95 = 0;
  std::vector<double> position_1sigma;  ///< per sample, in the samples' order (for plots)
};

/// From the covariance of the free parameters (free x free, the order of the samples'
/// Jacobian columns). Entries that are not finite give NaN figures.
PoseErrorPrediction predict_pose_errors(const WorkspaceSamples& samples,
                                        const MatrixXd& covariance);

/// The `probability` quantile of |e| for e ~ N(0, covariance) in 3-D: |e|^2 = sum l_i z_i^2
/// (l_i the eigenvalues). Approximated by the scaled chi-square with the same mean and
/// variance (Satterthwaite / Box 1954: c chi2_nu, c = sum l^2 / sum l, nu = (sum l)^2 /
/// sum l^2), exact when the eigenvalues are equal; within 2 % of the exact value at 95 % for
/// any eigenvalues (checked against a Monte Carlo in the tests).
double error_norm_quantile(const Matrix3d& covariance, double probability);

/// The quantile of the chi-square distribution with nu > 0 degrees of freedom (bisection on
/// the regularised incomplete gamma function).
double chi_square_quantile(double probability, double nu);

/// Standard deviation of each free parameter of the nominal model, i.e. how far the real
/// machine is expected to be from the nominal values: the parameter's prior_std when it has
/// one, else the std of its simulated error U[-e, e], e / sqrt(3), with e the parameter's
/// error_half_width or else `default_error_mm` / `default_error_rad` by unit.
VectorXd nominal_parameter_std(const MeasurementModel& model, const std::vector<int>& free_indices,
                               double default_error_mm = 5, double default_error_rad = 0.01);

/// The JSON object of a prediction: position_rms_mm, position_mean_1sigma_mm, ...
nlohmann::ordered_json to_json(const PoseErrorPrediction& p);

/// A calibration's predicted pose error next to the nominal model's: whether calibrating is
/// expected to make the machine more accurate at all.
struct AccuracyComparison {
  bool computed = false;
  std::string why_not;             ///< when not computed
  PoseErrorPrediction calibrated;  ///< from the estimate's covariance
  PoseErrorPrediction nominal;     ///< from nominal_parameter_std (prior or simulated spread)
  /// The calibrated model's predicted RMS position error (and orientation error, where the
  /// nominal one is not 0) is below the nominal model's.
  bool expected_to_beat_nominal = false;
};

/// Workspace samples at `params` (full vector; `samples` of them, seed `seed`) and both
/// predictions; never throws (a failure is why_not).
AccuracyComparison compare_with_nominal(const MeasurementModel& model, const VectorXd& params,
                                        const std::vector<int>& free_indices,
                                        const MatrixXd& covariance, int samples = 200,
                                        std::uint64_t seed = 1);
nlohmann::ordered_json to_json(const AccuracyComparison& a);
/// A few lines for the calibrate report, the last one saying plainly when calibrating is
/// not expected to beat the nominal model.
std::string to_text(const AccuracyComparison& a);

}  // namespace kincal
