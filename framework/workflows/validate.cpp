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
  result.iso9283 = iso9283_statistics(*model, values, loaded.data);
  // Without a point, the before/after comparison is of the readings: their residuals with
  // the model the calibration started from (a row the starting model cannot reach: none).
  if (request.before_values && !result.shows_pose) try {
      result.before_residuals = residual_matrix(model, loaded.data, *request.before_values);
    } catch (const std::runtime_error&) {
    }
  return result;
}

}  // namespace kincal
