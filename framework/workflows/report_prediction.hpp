#pragma once
// A calibration report file (format "kincal-calibration-report", what `kincal calibrate
// --json` writes) read for what it predicts about held-out readings: the noise (sigma_hat)
// and the estimated parameters' std and correlation. The reader of that format for the
// validate workflow; every number is checked to be one it can compute with.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "kincal/framework/analysis/calibration_report.hpp"
#include "kincal/framework/workflows/validate.hpp"

namespace kincal {

// What the calibration report says about the noise and the parameters.
struct ReportPrediction {
  double sigma_hat = NAN;
  bool weighted = false;
  std::string sigma_unit;
  std::vector<std::string> names;
  VectorXd std;
  MatrixXd correlation;
  std::string calibrated_sha256;
  VectorXd nominal;  ///< each parameter's value before the calibration (NaN: not given)
};

/// The largest calibration report read_report_prediction reads: 2 GiB, about 2·10^7
/// configurations' residuals (a report from 10^6 is about 90 MB).
inline constexpr std::size_t kMaxCalibrationReportBytes = std::size_t{2} << 30;

/// Reads `path`. Throws std::invalid_argument naming the file and field: not a calibration
/// report, a field missing or of the wrong type, a number that is not finite or out of its
/// range (a std of 1e300, a correlation beyond [-1, 1]), a parameter whose std is null.
ReportPrediction read_report_prediction(const std::string& path);
/// The same for a report already parsed (Python's report, a program's own); `source` names
/// it in messages as the path does.
ReportPrediction parse_report_prediction(const nlohmann::ordered_json& report,
                                         const std::string& source);

/// The prediction of `report` (read from `report_file`) for `model` (from `model_file`, the
/// calibrated model it was written with): sigma_hat, times reading_std when weighted, and
/// the parameters' covariance. Throws std::invalid_argument when it cannot predict: an exact
/// fit (sigma_hat null or 0), weighting that differs from the model's, unweighted readings
/// of several units, a parameter the model does not have.
ValidationPrediction prediction_from_report(const ReportPrediction& report,
                                            const MeasurementModel& model,
                                            const std::string& report_file,
                                            const std::string& model_file);

/// The values the calibration started from, as far as `report` gives them: `values` (the
/// calibrated model's) with each of the report's parameters at its nominal value, or nothing
/// when the report does not give every one (older reports). `prediction` is
/// prediction_from_report's for the same report (it maps the names to indices).
std::optional<VectorXd> values_before_calibration(const ReportPrediction& report,
                                                  const ValidationPrediction& prediction,
                                                  const VectorXd& values);

/// The same for a calibration's report in memory (CalibrateResult::report), for the model
/// with its estimate (model_with_values). Throws std::invalid_argument as above, and when the
/// calibration could not estimate every parameter's std.
ValidationPrediction prediction_from_calibration(const CalibrationReport& report,
                                                 const MeasurementModel& model);

}  // namespace kincal
