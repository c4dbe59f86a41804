#pragma once
// Accuracy in the field's terms (ISO 9283 style) for sensors that measure a point (a laser
// tracker's reflector, an optical tracker's marker): the 3-D position error per
// configuration, |predicted - measured| of the point's three position readings, and its mean,
// RMS and max over the configurations; the error predicted at the measured configurations
// from the fitted parameters' covariance; and the set of parameters a registration-only
// baseline fits (the frames that place the mechanism in the sensor's frame and the point on
// the end effector).

#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "kincal/framework/calibration/calibration_problem.hpp"

namespace kincal {

/// Whether any sensor of `model` measures a point (Sensor::position_reading_index >= 0).
bool measures_position(const MeasurementModel& model);

/// predicted - measured in the readings' units (configurations x readings; NaN where a
/// reading is missing) of `data` for `model` at the full parameter vector `values`. Throws
/// std::runtime_error with the reason when forward kinematics fails at a configuration.
MatrixXd residual_matrix(std::shared_ptr<const MeasurementModel> model, const Measurements& data,
                         const VectorXd& values);

/// The same for `problem`'s data at its free parameters `x`; throws as above.
MatrixXd residual_matrix(const CalibrationProblem& problem, const VectorXd& x);

/// RMS of a residual matrix's measured entries per reading unit ("mm", "rad").
std::map<std::string, double> residual_rms_by_unit(const MeasurementModel& model,
                                                   const MatrixXd& residuals);

/// One entry per configuration and point-measuring sensor whose readings were taken:
/// |(predicted - measured) of its x, y, z| in mm, from a residual matrix as above.
std::vector<double> position_errors(const MeasurementModel& model, const MatrixXd& residuals);

/// Mean, RMS and max of 3-D position errors (mm); NaN figures when there are none.
struct PositionErrorStats {
  int points = 0;
  double mean = NAN, rms = NAN, max = NAN;
};
PositionErrorStats summarize_position_errors(const std::vector<double>& errors);
/// {"points", "mean", "rms", "max"} (null for a figure that is not a number).
nlohmann::ordered_json to_json(const PositionErrorStats& stats);

/// The position error the fitted parameters' uncertainty predicts at each measured
/// configuration for the measured point: cov = J_p Cov J_p^T, J_p the three position rows of
/// the problem's Jacobian at x (all free parameters: mechanism and sensor), summarised as the
/// pose_accuracy predictions are (1 sigma = sqrt(trace), 95 % quantile of |e|; mean and max
/// over the configurations; RMS = sqrt(mean trace)). Not computed (points = 0) when the model
/// measures no point or the covariance is not finite.
struct PointErrorPrediction {
  int points = 0;
  double rms = NAN, mean_1sigma = NAN, max_1sigma = NAN, mean_95 = NAN, max_95 = NAN;
};
PointErrorPrediction predict_point_errors(const CalibrationProblem& problem, const VectorXd& x,
                                          const MatrixXd& covariance);
nlohmann::ordered_json to_json(const PointErrorPrediction& p);

/// The free indices (from `free`) a registration-only fit estimates: every sensor parameter
/// (the sensor's frame, the target or marker on the end effector) and the mechanism's
/// base.* and tool.* frames; the joints and links stay at their model values.
std::vector<int> registration_indices(const MeasurementModel& model, const std::vector<int>& free);

/// Of those, the translations that place the measured point on the end effector (tool.x, .y,
/// .z; a sensor's target or marker position): what a starting model most often does not know
/// (an imported arm's reflector starts at the flange's centre), so that its error before
/// calibration is measured with them fitted too ("nominal geometry, measured point located").
std::vector<int> measured_point_indices(const MeasurementModel& model,
                                        const std::vector<int>& free);

}  // namespace kincal
