#pragma once
// The validate workflow: a calibrated model's residuals on held-out measurements (readings
// that took no part in the calibration) against what the calibration predicts for them, the
// readings' noise plus the estimated parameters' uncertainty propagated; and, where the
// readings measure a point, its 3-D position error before and after. What `kincal validate`
// does between reading its files and writing its outputs, as one library call.
//
//   kincal::ValidateRequest request;
//   request.model = calibrated;                    // its nominal values are the ones tested
//   request.measurements.data = held_out;          // or load_measurements(path, ...)
//   request.prediction = kincal::prediction_from_calibration(result.report, *calibrated);
//   (report_prediction.hpp)
//   const kincal::ValidateResult v = kincal::validate(request);
//   // v.validation.verdict: consistent, larger_than_predicted, smaller_than_predicted

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "kincal/framework/analysis/calibration_report.hpp"
#include "kincal/framework/analysis/iso9283.hpp"
#include "kincal/framework/analysis/position_error.hpp"
#include "kincal/framework/analysis/validation.hpp"
#include "kincal/framework/calibration/measurement_loading.hpp"

namespace kincal {

/// What a calibration predicts for held-out readings: their noise std (the model's reading
/// order and units) and, optionally, parameters whose uncertainty is propagated.
struct ValidationPrediction {
  /// Empty: nothing predicts the residuals (a nominal model without reading_std); the errors
  /// are reported and the consistency test is not made.
  VectorXd noise_std;
  /// Where noise_std comes from, in words ("sigma_hat x reading_std", "reading_std", ...).
  std::string noise_source;
  /// Parameters (indices in the model) and their covariance; empty: taken as exact.
  std::vector<int> parameters;
  MatrixXd covariance;
};

/// The model's own reading_std when it states one, else nothing.
ValidationPrediction prediction_from_model(const MeasurementModel& model);

struct ValidateRequest {
  /// The calibrated model: its nominal values are the ones validated.
  std::shared_ptr<const MeasurementModel> model;
  /// The held-out measurements (load_measurements, or in memory with `lines` empty).
  LoadedMeasurements measurements;
  ValidationPrediction prediction;
  /// The values the calibration started from, for the "before" errors, and what they are in
  /// words (a file, "the report's nominal values"); unset: no "before".
  std::optional<VectorXd> before_values;
  std::string before_is;
  /// Two-sided significance of the chi-square test.
  double significance = 0.01;
  /// Names of the inputs, in messages only; may be empty.
  std::string model_file, data_file;
};

/// The 3-D position error of the measured point before and after: after = the model
/// validated, before = ValidateRequest::before_values. Not computed when the model measures no
/// point (measures_position).
struct PositionComparison {
  bool computed = false;
  std::string before_is;  ///< where "before" comes from; empty: no before
  std::vector<double> before_errors, after_errors;
  PositionErrorStats before, after;
};

struct ValidateResult {
  /// The residuals and the test; its verdict is "not_tested" when nothing predicts them.
  Validation validation;
  bool tested = false;
  /// Whether the readings measure a point of the mechanism: readings that do not (length
  /// gauges) agreeing says nothing of the pose (kPoseNotShown).
  bool shows_pose = false;
  PositionComparison position;
  /// ISO 9283 pose and distance statistics, when the data repeat configurations of a
  /// point-measuring sensor (framework/analysis/iso9283.hpp); empty otherwise.
  Iso9283Stats iso9283;
  /// Without a point: the readings' residuals with before_values (configurations x readings;
  /// empty when there is no before or it cannot predict every row).
  MatrixXd before_residuals;
  /// File line (or position from 1) of each held-out row.
  std::vector<int> lines;
  /// What a user should read, in order.
  std::vector<std::string> notes;
};

/// What held-out readings that measure no point cannot show.
extern const char* const kPoseNotShown;

/// Runs the validate workflow. Throws std::invalid_argument naming the data file and line
/// when a statistic would not be finite (no verdict on NaN), or when the model before
/// calibration cannot predict the data.
ValidateResult validate(const ValidateRequest& request);

}  // namespace kincal
