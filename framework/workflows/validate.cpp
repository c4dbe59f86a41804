#include "kincal/framework/workflows/validate.hpp"

#include <cstdio>
#include <numeric>
#include <stdexcept>

namespace kincal {

const char* const kPoseNotShown =
    "these held-out readings measure no point of the mechanism, so agreeing with them does not "
    "confirm its pose accuracy (a model can fit one gauge's lengths and still be millimetres "
    "off in pose); to check the pose, validate on configurations measured with a point or pose "
    "tracker, or with the gauge in a second placement";

ValidationPrediction prediction_from_calibration(const CalibrationReport& report,
                                                 const MeasurementModel& model) {
  const double sigma = report.uncertainty.sigma;
  if (!(sigma > 0))
    throw std::invalid_argument(
        "the calibration's sigma_hat is not positive (an exact fit says nothing about the "
        "noise); expected a calibration with more readings than parameters");
  if (report.weighted != model.weighted())
    throw std::invalid_argument(
        std::string("the calibration was ") + (report.weighted ? "" : "not ") +
        "weighted (reading_std) but the model " + (model.weighted() ? "states" : "states no") +
        " reading_std; expected the model the calibration was written for");
  ValidationPrediction p;
  const int k = model.num_readings();
  if (report.weighted) {
    p.noise_std = sigma * model.reading_std();
    p.noise_source = "sigma_hat x reading_std";
  } else {
    const std::vector<std::string> units = model.reading_units();
    for (const std::string& unit : units)
      if (unit != units.front())
        throw std::invalid_argument(
            "the calibration's sigma_hat pools readings of several units (no reading_std); "
            "state reading_std in the model and calibrate again");
    p.noise_std = VectorXd::Constant(k, sigma);
    p.noise_source = "sigma_hat";
  }
  const int n = static_cast<int>(report.names.size());
  for (const std::string& name : report.names) {
    const int index = model.parameters().find(name);
    if (index < 0)
      throw std::invalid_argument("the calibration's parameter '" + name +
                                  "' is not in the model; expected the model the calibration "
                                  "was written for");
    p.parameters.push_back(index);
  }
  const VectorXd& std = report.uncertainty.std;
  if (std.size() != n || !std.allFinite())
    throw std::invalid_argument(
        "the calibration could not estimate every parameter's std; validate without it to "
        "compare with the noise alone");
  p.covariance = std.asDiagonal() * report.uncertainty.correlation * std.asDiagonal();
  return p;
}

ValidationPrediction prediction_from_model(const MeasurementModel& model) {
  ValidationPrediction p;
  if (!model.weighted()) {
    p.noise_source = "none";
    return p;
  }
  p.noise_std = model.reading_std();
  p.noise_source = "reading_std";
  return p;
}

namespace {

PositionComparison compare_positions(const std::shared_ptr<const MeasurementModel>& model,
                                     const Measurements& data, const MatrixXd& after_residuals,
                                     const std::optional<VectorXd>& before_values,
                                     const std::string& before_is, const std::string& data_file) {
  PositionComparison c;
  if (!measures_position(*model)) return c;
  c.computed = true;
  c.after_errors = position_errors(*model, after_residuals);
  c.after = summarize_position_errors(c.after_errors);
  if (!before_values) return c;
  try {
    c.before_errors = position_errors(*model, residual_matrix(model, data, *before_values));
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument(data_file + ": the model before calibration (" + before_is +
                                ") cannot predict the data: " + e.what());
  }
  c.before = summarize_position_errors(c.before_errors);
  c.before_is = before_is;
  return c;
}

}  // namespace

ValidateResult validate(const ValidateRequest& request) {
  if (!request.model) throw std::invalid_argument("validate: the request has no model");
  const std::shared_ptr<const MeasurementModel>& model = request.model;
  const LoadedMeasurements& loaded = request.measurements;
  ValidateResult result;
  result.lines = loaded.lines;
  if (result.lines.empty()) {
    result.lines.resize(static_cast<std::size_t>(loaded.data.size()));
    std::iota(result.lines.begin(), result.lines.end(), 1);
  }
  if (!loaded.copied_rows_note.empty()) result.notes.push_back(loaded.copied_rows_note);

  const VectorXd values = model->parameters().nominal_values();
  ValidationInput input;
  result.tested = request.prediction.noise_std.size() > 0;
  input.noise_std = result.tested ? request.prediction.noise_std
                                  : VectorXd(VectorXd::Ones(model->num_readings()));
  input.parameters = request.prediction.parameters;
  input.covariance = request.prediction.covariance;
  input.significance = request.significance;
  result.shows_pose = measures_position(*model);
  Validation& v = result.validation;
  try {
    v = validate_held_out(model, loaded.data, values, input);
  } catch (const NonFiniteValidation& e) {  // no verdict on NaN: name the line instead
    char residual[40];
    std::snprintf(residual, sizeof residual, "%.3g", e.residual);
    throw std::invalid_argument(
        request.data_file + ":" + std::to_string(result.lines[e.configuration]) + ": field '" +
        model->reading_names()[e.reading] + "': predicted - measured is " + residual +
        ", which makes the held-out statistics overflow (not finite: no verdict); "
        "expected readings on the scale of the machine");
  } catch (const std::exception& e) {
    throw std::invalid_argument(request.data_file + ": " + e.what());
  }
  if (!result.tested) v.verdict = "not_tested";
  result.position = compare_positions(model, loaded.data, v.residuals, request.before_values,
                                      request.before_is, request.data_file);
  // Without a point, the before/after comparison is of the readings: their residuals with
  // the model the calibration started from (a row the starting model cannot reach: none).
  if (request.before_values && !result.shows_pose) try {
      result.before_residuals = residual_matrix(model, loaded.data, *request.before_values);
    } catch (const std::runtime_error&) {
    }
  return result;
}

}  // namespace kincal
