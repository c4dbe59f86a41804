#include "kincal/framework/workflows/validate_report.hpp"

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <sstream>

namespace kincal {

namespace {

using Json = nlohmann::ordered_json;

Json number(double v) { return std::isfinite(v) ? Json(v) : Json(); }

std::string format(const char* fmt, double a) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, a);
  return buf;
}

std::string format_text(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string format_text(const char* fmt, ...) {
  char buf[512];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, args);
  va_end(args);
  return buf;
}

}  // namespace

std::string validation_text(const ValidateRequest& request, const ValidateResult& result,
                            const std::string& model_name, const std::string& data_name) {
  const Validation& v = result.validation;
  const bool tested = result.tested;
  const std::string& noise_source = request.prediction.noise_source;
  const PositionComparison& position = result.position;
  std::ostringstream text;
  text << "held-out validation of " << model_name << " on " << data_name << ": " << v.configurations
       << " configurations, " << v.readings << " readings\n";
  // Repeats test the noise at their configurations, not the calibration elsewhere.
  if (request.measurements.repeated_configurations > 0)
    text << "repeats: " << request.measurements.repeat_rows << " rows measure only "
         << request.measurements.repeated_configurations
         << " configuration(s) again: they test the noise and the prediction there, and "
            "the parameters' error is common to all of them (counted once by the test)\n";
  if (tested)
    text << "predicted: noise = " << noise_source
         << (v.parameter_uncertainty
                 ? " + the parameters' uncertainty from the report (J Sigma J^T)"
                 : " alone (no --report: the parameters are taken as exact)")
         << "\n";
  else
    text << "predicted: nothing (no --report and no reading_std in the model): the errors "
            "are reported, the consistency test is not made\n";
  for (const auto& p : v.per_reading) {
    if (!p.count) continue;
    if (tested)
      text << format_text(
          "  %-12s %-4s %5d readings  RMS %-10.4g max %-10.4g predicted RMS %-10.4g "
          "(noise %.4g, parameters %.4g)\n",
          p.name.c_str(), p.unit.c_str(), p.count, p.rms, p.max, p.predicted_rms, p.noise_std,
          p.parameter_rms);
    else
      text << format_text("  %-12s %-4s %5d readings  RMS %-10.4g max %-10.4g\n", p.name.c_str(),
                          p.unit.c_str(), p.count, p.rms, p.max);
  }
  if (position.computed) {
    text << "3-D position error of the measured point, mm (" << position.after.points
         << " points):\n";
    if (!position.before_is.empty())
      text << format_text("  before  mean %9.4g  RMS %9.4g  max %9.4g   (%s)\n",
                          position.before.mean, position.before.rms, position.before.max,
                          position.before_is.c_str());
    text << format_text("  %-7s mean %9.4g  RMS %9.4g  max %9.4g   (%s)\n",
                        position.before_is.empty() ? "error" : "after", position.after.mean,
                        position.after.rms, position.after.max, model_name.c_str());
  }
  if (result.iso9283.computed()) text << iso9283_text(result.iso9283, result.lines);
  if (tested)
    text << "standardized RMS " << format("%.3f", v.standardized_rms)
         << " (1 = as predicted), chi-square " << format("%.4g", v.chi_square) << " on "
         << v.readings << " degrees of freedom: P(larger) " << format("%.3g", v.p_larger)
         << ", P(smaller) " << format("%.3g", v.p_smaller) << "\n";
  if (v.verdict == "not_tested")
    text << "not tested: give --report (the calibration's) or state reading_std in the "
            "model to test the residuals against a prediction\n";
  else if (v.verdict == "consistent")
    text << "consistent: the held-out residuals are what the calibration predicts\n";
  else if (v.verdict == "larger_than_predicted")
    text << "NOT consistent: the held-out residuals are larger than predicted (the "
            "model misses something, or its uncertainty is understated)\n";
  else
    text << "smaller than predicted: the stated noise or uncertainty is pessimistic\n";
  if (!result.shows_pose) text << "note: " << kPoseNotShown << "\n";
  return text.str();
}

nlohmann::ordered_json validation_json(const ValidateRequest& request, const ValidateResult& result,
                                       const std::string& report_file,
                                       const nlohmann::ordered_json& target) {
  const Validation& v = result.validation;
  const bool tested = result.tested;
  const bool shows_pose = result.shows_pose;
  const std::string& noise_source = request.prediction.noise_source;
  const PositionComparison& position = result.position;
  const MatrixXd& before_residuals = result.before_residuals;
  const int k = request.model->num_readings();
  Json out;
  out["format"] = "kincal-validation";
  out["version"] = 1;
  out["model"] = request.model_file;
  out["data"] = request.data_file;
  out["report"] = report_file.empty() ? Json() : Json(report_file);
  out["configurations"] = v.configurations;
  out["readings"] = v.readings;
  out["skipped_lines"] = request.measurements.skipped_lines;
  out["dropped_readings"] = request.measurements.dropped_readings;
  const bool one_unit = v.rms_by_unit.size() == 1;
  out["residual_rms"] = one_unit ? Json(v.rms_by_unit.begin()->second) : Json();
  out["residual_max"] = one_unit ? Json(v.max_by_unit.begin()->second) : Json();
  out["residual_rms_by_unit"] = v.rms_by_unit;
  out["residual_max_by_unit"] = v.max_by_unit;
  out["noise"] = tested ? Json(noise_source) : Json();
  out["parameter_uncertainty"] = v.parameter_uncertainty;
  Json readings = Json::array();
  for (const auto& p : v.per_reading)
    readings.push_back({{"name", p.name},
                        {"unit", p.unit},
                        {"readings", p.count},
                        {"rms", p.count ? Json(p.rms) : Json()},
                        {"max", p.count ? Json(p.max) : Json()},
                        {"noise_std", tested ? Json(p.noise_std) : Json()},
                        {"parameter_rms", p.count ? Json(p.parameter_rms) : Json()},
                        {"predicted_rms", p.count && tested ? Json(p.predicted_rms) : Json()}});
  out["per_reading"] = readings;
  if (position.computed) {
    Json errors = {{"before", position.before_is.empty() ? Json() : to_json(position.before)},
                   {"after", to_json(position.after)}};
    errors["before_model"] = position.before_is.empty() ? Json() : Json(position.before_is);
    errors["after_model"] = request.model_file;
    out["position_error_mm"] = errors;
    if (result.iso9283.computed()) out["iso9283"] = iso9283_json(result.iso9283, result.lines);
  }
  out["duplicate_rows"] = request.measurements.duplicate_rows;
  out["repeated_configurations"] = request.measurements.repeated_configurations;
  out["repeat_rows"] = request.measurements.repeat_rows;
  out["chi_square"] = tested ? number(v.chi_square) : Json();
  out["degrees_of_freedom"] = v.readings;
  out["standardized_rms"] = tested ? number(v.standardized_rms) : Json();
  out["p_larger"] = tested ? number(v.p_larger) : Json();
  out["p_smaller"] = tested ? number(v.p_smaller) : Json();
  out["significance"] = request.significance;
  out["verdict"] = v.verdict;
  // What the verdict is about: readings. Without a sensor that measures a point, readings
  // that agree say nothing of the pose (a gauge's length is one number of six).
  out["pose_accuracy_shown"] = shows_pose;
  out["pose_accuracy_note"] = shows_pose ? Json() : Json(kPoseNotShown);
  if (!target.is_null()) out["target"] = target;
  Json residuals = Json::array();
  const auto names = request.model->reading_names();
  for (int c = 0; c < v.residuals.rows(); ++c) {
    Json row;
    row["line"] = result.lines[c];
    for (int i = 0; i < k; ++i) row[names[i]] = number(v.residuals(c, i));
    if (position.computed &&
        position.after_errors.size() == static_cast<std::size_t>(v.residuals.rows())) {
      row["position_error_mm"] = number(position.after_errors[c]);
      if (position.before_errors.size() == position.after_errors.size())
        row["position_error_before_mm"] = number(position.before_errors[c]);
    }
    if (before_residuals.rows() == v.residuals.rows()) {
      row["before"] = Json::object();
      for (int i = 0; i < k; ++i) row["before"][names[i]] = number(before_residuals(c, i));
    }
    residuals.push_back(row);
  }
  out["residuals"] = residuals;
  return out;
}

}  // namespace kincal
