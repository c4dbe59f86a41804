#pragma once
// What a calibration from measured data reports: the fit, the estimated parameters with
// their uncertainty, per-configuration residuals with outlier flags, and identifiability.

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "kincal/framework/analysis/identifiability.hpp"
#include "kincal/framework/analysis/pose_accuracy.hpp"
#include "kincal/framework/analysis/position_error.hpp"
#include "kincal/framework/analysis/residual_structure.hpp"
#include "kincal/framework/calibration/calibration_problem.hpp"
#include "kincal/framework/calibration/fit_check.hpp"
#include "kincal/framework/least_squares/robust_loss.hpp"
#include "kincal/framework/least_squares/solver.hpp"
#include "kincal/framework/least_squares/uncertainty.hpp"

namespace kincal {

/// The probability that clean Gaussian data of any size has one or more configurations
/// flagged as outliers (the family-wise false-alarm rate of the flags).
constexpr double kOutlierFamilyProbability = 0.05;

/// z with P(|Z| > z) = p for Z standard normal (0 < p < 1).
double normal_two_sided_quantile(double p);

struct CalibrationReport {
  std::string model_file, data_file;
  std::string formulation = "nested";  ///< nested or implicit (calibration_solve.hpp)
  /// Why the formulation asked for is not the one solved (CalibrationSolve::note), or empty.
  std::string formulation_note;
  std::string loss = "none";  ///< the robust loss the fit used and the uncertainty accounts for
  /// The solver's settings in force (limits, tolerances, threads, backend options), so that a
  /// report says how it was obtained; the callback and bounds are not recorded.
  SolverOptions solver_options;
  Summary summary;
  std::vector<std::string> names;  ///< free parameters, problem order
  std::vector<std::string> units;  ///< their units ("mm", "rad")
  /// Free parameters in their units; angles on the branch nearest nominal (nominal +- pi).
  VectorXd nominal, estimate;
  ParameterUncertainty uncertainty;
  int num_configurations = 0;
  std::vector<std::string> reading_names, reading_units;
  /// Each reading's stated noise std (its unit) when the model states reading_std (weighted).
  VectorXd reading_std;
  /// Readings measured (not missing), per sensor, in the model's sensor order.
  std::vector<std::pair<std::string, int>> readings_per_sensor;
  int num_readings = 0;  ///< measured readings in all: the residuals of the fit
  /// The model states the readings' noise (reading_std), and residuals were divided by it.
  bool weighted = false;
  std::vector<int> lines;  ///< file line of each configuration
  /// Configurations x readings, predicted - measured in the readings' units; NaN where the
  /// reading is missing.
  MatrixXd residuals;
  /// A configuration is an outlier when one of its residuals, divided by its reading's std
  /// (1 when the model states none), exceeds the threshold of its reading's unit:
  ///   outlier_z * s_unit,  s_unit = 1.4826 * median |residual| over that unit's readings
  /// (a robust estimate of the noise std), at least 1e-9, with outlier_z the two-sided
  /// normal quantile at which clean Gaussian data of num_readings residuals flags any
  /// configuration with probability kOutlierFamilyProbability (Bonferroni):
  ///   P(|z| > outlier_z) = kOutlierFamilyProbability / num_readings.
  /// outlier_threshold is the threshold of the first unit (the only one in most models).
  double outlier_threshold = 0;
  std::map<std::string, double> outlier_threshold_by_unit;
  double outlier_z = 0;
  std::vector<bool> outlier;
  /// Under a robust loss: the noise estimate from the residuals as the loss sees them (psi),
  /// which Huber's covariance uses; uncertainty.sigma is then the std of the unweighted
  /// residuals of the configurations not flagged (inliers), on m_inliers - n degrees of
  /// freedom, the figure held-out data are compared with. NaN without a loss.
  double psi_sigma = NAN;
  int inlier_readings = 0;
  /// RMS and max |residual| over the measured readings of each unit.
  std::map<std::string, double> residual_rms, residual_max;
  Identifiability identifiability;  ///< at the estimate
  /// The model's parameter-only constraints at the estimate, one entry per residual; they
  /// count in the cost, the covariance and the identifiability like readings.
  struct ConstraintResidual {
    std::string type, label, unit;
    double residual = 0;  ///< unweighted, in `unit`
    double std = 0;       ///< as the model states it
  };
  std::vector<ConstraintResidual> constraints;
  /// Parameters the user freed but the analysis fixed (--allow-rank-deficient).
  std::vector<std::string> fixed_by_identifiability;
  /// For each of fixed_by_identifiability, what the data see of it (dependent_effect).
  std::vector<std::string> fixed_effects;
  std::vector<int> skipped_lines;  ///< rows dropped as unreachable (--skip-bad-rows)
  /// Readings dropped because their sensor gives none there (Sensor::reads_at), one line
  /// each: "line 12: laser: beam misses the plane".
  std::vector<std::string> dropped_readings;
  /// Plain-language warnings about the data or the model found by the checks around the
  /// solve (e.g. forward kinematics of the data far from home_pose); one sentence each.
  std::vector<std::string> warnings;
  /// A prior was used: the estimate is MAP, uncertainty.std the posterior std.
  bool prior = false;
  FitCheck fit_check;
  /// The residuals' shape: noise or a model error (residual_structure.hpp).
  ResidualStructure structure;
  /// The estimate's branch (framework/calibration/equivalent_solutions.hpp), filled by the
  /// caller that mapped it: what was mapped to the branch nearest nominal, and a map the
  /// mechanism proposed that was not exact.
  std::vector<std::string> branch_mapped;
  std::string branch_rejected;
  /// Free angles of the geometry (outside the registration frames) still more than pi/2
  /// from their nominal: "shoulder_lift_joint.offset 3.141 rad (nominal 0)".
  std::vector<std::string> off_branch;
  /// Free parameters outside the registration frames whose correction exceeds
  /// kFarBeyondTolerance x their tolerance (parameter_tolerances), largest ratio first.
  struct FarCorrection {
    std::string name, unit;
    double change = 0, tolerance = 0;
    bool assumed = false;  ///< the tolerance is kincal's assumption, not the model's
  };
  std::vector<FarCorrection> far_corrections;
  /// Rows that repeat an earlier row exactly, actuators and readings (counted once: a copy is
  /// not a second measurement), and configurations measured more than once with different
  /// readings (repeats: kept, their scatter is the noise). Filled by the caller that read the
  /// data (data_checks.hpp: find_repeats).
  int duplicate_rows = 0;
  int repeated_configurations = 0;
  int repeat_rows = 0;
  /// Predicted pose error over the workspace from the estimate's covariance, next to the
  /// nominal model's (compare_with_nominal at the estimate).
  AccuracyComparison predicted_accuracy;
  /// The readings measure a point of the mechanism (measures_position). When they do not (a
  /// length gauge), residuals that agree, fitted or held out, do not confirm the pose
  /// accuracy: the report says so (kPoseAccuracyNotShown) and what would.
  bool pose_accuracy_shown = true;

  /// Accuracy in the field's terms, for models with a point-measuring sensor
  /// (position_error.hpp; points = 0 otherwise): the measured 3-D position error on the
  /// calibration data with the starting values and with the estimate, and the error the
  /// estimate's covariance predicts for the measured point at the measured configurations.
  PositionErrorStats position_before, position_after;
  PointErrorPrediction predicted_point;
  /// A registration-only baseline: only the frames that place the mechanism in the sensor's
  /// frame and the point on the end effector fitted (registration_indices), the joints and
  /// links at their starting values. Filled by the caller (it needs the solver).
  struct Baseline {
    bool computed = false;
    std::string why_not;
    std::vector<std::string> names;  ///< the parameters it fitted
    std::string termination;
    std::map<std::string, double> residual_rms;  ///< per unit, on the calibration data
    PositionErrorStats position;
  } registration;
  /// The nominal geometry with only the measured point located on the end effector
  /// (measured_point_indices): the error of the starting model as a user means it when the
  /// model did not know where the reflector is. Filled by the caller like `registration`.
  Baseline point_located;
  /// K-fold cross-validation (calibrate --folds K), filled by the caller: held-out errors of
  /// the full calibration and of the registration-only fit.
  struct Folds {
    int folds = 0;  ///< 0: not run
    int failed = 0;
    std::string failure;
    std::map<std::string, double> residual_rms, registration_residual_rms;
    PositionErrorStats position, registration_position;
  } cross_validation;
};

/// What a calibration from readings that measure no point cannot show, and what would.
inline constexpr const char* kPoseAccuracyNotShown =
    "the readings measure no point of the mechanism, so residuals that agree with them, on the "
    "calibration data or held out, do not confirm its pose accuracy (a model can fit one "
    "gauge's lengths and still be millimetres off in pose), and the predicted pose error comes "
    "from the parameters' covariance under the model, not from a measured pose; to check the "
    "pose, measure configurations with a point or pose tracker, or with the gauge in a second "
    "placement, and run kincal validate on them";

/// Fills everything but the file names and the two lists above from the problem solved at x
/// with the robust loss `loss` (none: plain least squares); the standard deviations then use
/// that loss's IRLS weights (estimate_uncertainty). Missing readings take no part: the
/// statistics, the uncertainty and the identifiability are those of the measured readings
/// alone. Returns with empty residuals when they cannot be computed at x.
///
/// `prior_precision` (Prior::precision(), per free parameter; empty or all 0 = no prior): x is
/// a MAP estimate, and the standard deviations are the posterior's, with each parameter's
/// data share (estimate_posterior_uncertainty); the identifiability says what the prior
/// determines (add_prior).
CalibrationReport make_calibration_report(const CalibrationProblem& problem, const VectorXd& x,
                                          const Summary& summary, const std::vector<int>& lines,
                                          const RobustLoss& loss = {},
                                          const IdentifiabilityOptions& options = {},
                                          const VectorXd& prior_precision = {});

/// The fit check of a report whose uncertainty is filled, from the measured readings'
/// residuals as the problem weighs them (divided by their reading_std).
FitCheck check_fit(const CalibrationReport& r, const VectorXd& measured_whitened);

/// What sigma_hat is measured in: the readings' unit, "reading_std" (multiples of the stated
/// reading std) or "mixed".
std::string sigma_unit(const CalibrationReport& report);
/// What an outlier flag means, in words (the level and why it was chosen).
std::string outlier_meaning(const CalibrationReport& report);

nlohmann::ordered_json to_json(const Identifiability& a);
nlohmann::ordered_json to_json(const CalibrationReport& report);

/// Human-readable forms, several lines each.
std::string to_text(const Identifiability& a);
std::string to_text(const CalibrationReport& report);

}  // namespace kincal
