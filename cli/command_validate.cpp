// kincal validate: residuals of a calibrated model on held-out data (readings that took no
// part in the calibration) against what the calibration predicts for them: the readings'
// noise plus, with --report, the estimated parameters' uncertainty propagated.

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>

#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/html_pages.hpp"
#include "kincal/cli/memory_check.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/cli/sha256.hpp"
#include "kincal/cli/shared_options.hpp"
#include "kincal/cli/target_accuracy.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/io/json_input.hpp"
#include "kincal/framework/workflows/validate.hpp"
#include "kincal/models/model_io.hpp"

namespace kincal::cli {

namespace {

using Json = nlohmann::ordered_json;

Json number(double v) { return std::isfinite(v) ? Json(v) : Json(); }

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

double report_number(const Json& value, const std::string& where) {
  if (!value.is_number()) throw CliError(where + ": expected a number");
  return value.get<double>();
}

// A report's number must be one validate can compute with: its square a finite, normal
// double (so 5e-324 and 1e300 are refused as a noise or a std), within [low, high].
double report_number_in(const Json& value, const std::string& where, double low, double high,
                        const char* expected) {
  const double v = report_number(value, where);
  if (!(v >= low && v <= high)) {
    char text[40];
    std::snprintf(text, sizeof text, "%.6g", v);
    throw CliError(where + " is " + text + "; expected " + expected);
  }
  return v;
}
constexpr double kLargest = 1e150, kSmallest = 1e-150;

ReportPrediction read_report(const std::string& path) {
  const Json report = read_json_file(path, "calibration report");
  if (!report.is_object() || report.value("format", "") != "kincal-calibration-report")
    throw CliError(path + ": expected a calibration report (format \"kincal-calibration-report\")");
  ReportPrediction p;
  for (const char* key : {"sigma_hat", "weighted", "parameters", "correlation"})
    if (!report.contains(key)) throw CliError(path + ": no '" + key + "' field");
  if (!report["sigma_hat"].is_null()) {
    p.sigma_hat = report_number(report["sigma_hat"], path + ": sigma_hat");
    if (p.sigma_hat != 0)  // 0 (an exact fit) is refused with its reason by the caller
      report_number_in(report["sigma_hat"], path + ": sigma_hat", kSmallest, kLargest,
                       "a finite noise >= 1e-150 and <= 1e150");
  }
  if (!report["weighted"].is_boolean()) throw CliError(path + ": weighted: expected true or false");
  p.weighted = report["weighted"].get<bool>();
  p.sigma_unit = report.value("sigma_hat_unit", "");
  const Json& parameters = report["parameters"];
  if (!parameters.is_array()) throw CliError(path + ": parameters: expected an array");
  const int n = static_cast<int>(parameters.size());
  p.std.resize(n);
  p.nominal = VectorXd::Constant(n, NAN);
  for (int i = 0; i < n; ++i) {
    const Json& entry = parameters[i];
    const std::string where = path + ": parameters[" + std::to_string(i) + "]";
    if (!entry.is_object() || !entry.contains("name") || !entry["name"].is_string() ||
        !entry.contains("std"))
      throw CliError(where + ": expected {\"name\": ..., \"std\": ...}");
    p.names.push_back(entry["name"].get<std::string>());
    if (entry.contains("nominal") && entry["nominal"].is_number())
      p.nominal[i] = entry["nominal"].get<double>();
    if (entry["std"].is_null())
      throw CliError(where +
                     ": std is null (the calibration could not estimate it); "
                     "validate without --report to compare with the noise alone");
    p.std[i] = report_number_in(entry["std"], where + ".std", 0, kLargest,
                                "a finite std >= 0 and <= 1e150");
  }
  const Json& correlation = report["correlation"];
  if (!correlation.is_array() || static_cast<int>(correlation.size()) != n)
    throw CliError(path + ": correlation: expected " + std::to_string(n) + " x " +
                   std::to_string(n) + " numbers");
  p.correlation.resize(n, n);
  for (int i = 0; i < n; ++i) {
    if (!correlation[i].is_array() || static_cast<int>(correlation[i].size()) != n)
      throw CliError(path + ": correlation[" + std::to_string(i) + "]: expected " +
                     std::to_string(n) + " numbers");
    for (int j = 0; j < n; ++j)
      p.correlation(i, j) = report_number_in(
          correlation[i][j],
          path + ": correlation[" + std::to_string(i) + "][" + std::to_string(j) + "]", -1 - 1e-9,
          1 + 1e-9, "a correlation in [-1, 1]");
  }
  if (report.contains("calibrated_model") && !report["calibrated_model"].is_null()) {
    const Json& entry = report["calibrated_model"];
    if (!entry.is_object() || !entry.contains("sha256") || !entry["sha256"].is_string())
      throw CliError(path +
                     ": calibrated_model: expected {\"file\": ..., \"sha256\": ...} or null");
    p.calibrated_sha256 = entry["sha256"].get<std::string>();
  }
  return p;
}

// The report must be the one written with the model file: calibrate records the SHA-256 of
// the model it wrote, as `kincal verify` checks. A report without one (calibrate without
// --out) cannot be checked, and validate says so.
void check_report_is_for_model(const std::string& report_file, const std::string& expected,
                               const std::string& model_file) {
  if (expected.empty()) {
    note("validate", report_file +
                         " names no calibrated model (calibrate ran without --out), so it cannot "
                         "be checked to be the report of " +
                         model_file);
    return;
  }
  const std::string actual = model_file_sha256(model_file);
  if (actual != expected)
    throw CliError(model_file + " is not the calibrated model " + report_file +
                   " describes: its SHA-256 is " + actual + ", the report's " + expected +
                   "; expected the model written with this report (kincal verify checks a pair)");
}

std::string format(const char* fmt, double a) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, a);
  return buf;
}

}  // namespace

int run_validate(const Args& args) {
  po::options_description options("kincal validate");
  options.add_options()("model", po::value<std::string>(), "calibrated model file (JSON)")(
      "data", po::value<std::string>(),
      "held-out measurement file (CSV): configurations the calibration did not use")(
      "report", po::value<std::string>(),
      "the calibration's report (JSON) written with --model (its calibrated_model.sha256 "
      "must be the model file's): its sigma_hat is the noise, and its parameters' std "
      "and correlation are propagated to the readings")(
      "before", po::value<std::string>(),
      "the model the calibration started from (JSON, the same parameters as --model): the "
      "3-D position error \"before\" is computed with its values (default with --report: the "
      "report's nominal values of the parameters it fitted)")(
      "skip-bad-rows", po::bool_switch(), "drop rows the model cannot reach instead of failing")(
      "html", po::value<std::string>(),
      "write the result for people to FILE: one self-contained HTML page");
  add_json_option(options, "the result");
  add_noise_std_option(options,
                       "predicts the held-out residuals with it, instead of the report's "
                       "sigma_hat or the model's reading_std");
  add_data_size_option(options);
  add_target_option(options);
  po::variables_map vm;
  if (!parse_command_line("validate", args, options, vm)) return 0;
  const std::optional<TargetAccuracy> target = target_option(vm);
  if (!vm.count("model")) throw CliError("--model FILE is required (the calibrated model)");
  if (!vm.count("data")) throw CliError("--data FILE is required (held-out measurements)");
  OutputPlan plan;
  for (const char* option : {"model", "data", "report", "before"})
    if (vm.count(option)) plan.input(std::string("--") + option, vm[option].as<std::string>());
  if (vm.count("json")) plan.output("--json", vm["json"].as<std::string>());
  if (vm.count("html")) plan.output("--html", vm["html"].as<std::string>());
  plan.check();

  const std::string model_file = vm["model"].as<std::string>();
  const std::string data_file = vm["data"].as<std::string>();
  std::shared_ptr<MeasurementModel> model = load_model_option(vm);
  const VectorXd values = model->parameters().nominal_values();
  const int k = model->num_readings();

  ValidateRequest request;
  request.model_file = model_file;
  request.data_file = data_file;
  ValidationPrediction& prediction = request.prediction;
  ReportPrediction report;
  if (vm.count("report")) {
    const std::string report_file = vm["report"].as<std::string>();
    report = read_report(report_file);
    check_report_is_for_model(report_file, report.calibrated_sha256, model_file);
    if (!(report.sigma_hat > 0))
      throw CliError(report_file +
                     ": sigma_hat is null or 0 (an exact fit says nothing about the noise); "
                     "expected a calibration with more readings than parameters");
    if (report.weighted != model->weighted())
      throw CliError(report_file + ": weighted is " + (report.weighted ? "true" : "false") +
                     " but " + model_file + (model->weighted() ? " states" : " states no") +
                     " reading_std; expected the model the report was written for");
    if (!report.weighted && report.sigma_unit == "mixed")
      throw CliError(report_file +
                     ": sigma_hat pools mm and rad (no reading_std); state reading_std in the "
                     "model and calibrate again");
    // Weighted: sigma_hat is the ratio of the scatter to the stated std; otherwise it is the
    // std itself, in the readings' one unit.
    prediction.noise_std = report.weighted ? VectorXd(report.sigma_hat * model->reading_std())
                                           : VectorXd(VectorXd::Constant(k, report.sigma_hat));
    prediction.noise_source = report.weighted ? "sigma_hat x reading_std" : "sigma_hat";
    for (const auto& name : report.names) {
      const int index = model->parameters().find(name);
      if (index < 0)
        throw CliError(report_file + ": parameter '" + name + "' is not in " + model_file +
                       "; expected the model the report was written for");
      prediction.parameters.push_back(index);
    }
    prediction.covariance = report.std.asDiagonal() * report.correlation * report.std.asDiagonal();
  } else {
    // Without a report, the model's reading_std, if any; else nothing predicts the residuals
    // (a nominal model): the errors are reported, the chi-square test is not made.
    prediction = prediction_from_model(*model);
  }
  if (vm.count("noise-std")) {
    prediction.noise_std = noise_std_per_reading(vm, *model);
    prediction.noise_source = "--noise-std";
  }

  // "Before": --before's values, or the report's starting values of what it fitted.
  if (vm.count("before")) {
    const std::string before_file = vm["before"].as<std::string>();
    const auto before = load_model(before_file);
    const auto& a = model->parameters();
    const auto& b = before->parameters();
    bool same = a.size() == b.size() && model->reading_names() == before->reading_names();
    for (int i = 0; same && i < a.size(); ++i) same = a[i].name == b[i].name;
    if (!same)
      throw CliError(before_file + ": not the same parameters and readings as " + model_file +
                     "; expected the model the calibration started from");
    request.before_values = before->parameters().nominal_values();
    request.before_is = before_file;
  } else if (vm.count("report") && report.nominal.allFinite()) {
    VectorXd v = values;
    for (std::size_t i = 0; i < report.names.size(); ++i)
      v[prediction.parameters[i]] = report.nominal[static_cast<int>(i)];
    request.before_values = v;
    request.before_is = vm["report"].as<std::string>() + " (its parameters' nominal values)";
  }

  request.measurements =
      load_measurements("validate", data_file, *model, values, vm["skip-bad-rows"].as<bool>(),
                        model_file, data_limits(vm));
  const LoadedData& loaded = request.measurements;
  check_memory(data_file, loaded.data.size(),
               k * solve_bytes_per_row(static_cast<int>(prediction.parameters.size())),
               "configuration");
  request.model = model;
  const ValidateResult result = validate(request);
  for (const std::string& text : result.notes) note("validate", text);
  const Validation& v = result.validation;
  const bool tested = result.tested;
  const bool shows_pose = result.shows_pose;
  const std::string& noise_source = prediction.noise_source;
  const PositionComparison& position = result.position;
  const MatrixXd& before_residuals = result.before_residuals;
  const Json target_result =
      target ? measured_target(
                   *target, position.computed ? Json{{"after", to_json(position.after)}} : Json(),
                   "these held-out readings measure no point of the mechanism")
             : Json();
  const bool json_to_stdout = (vm.count("json") && plan.to_stdout("--json")) ||
                              (vm.count("html") && plan.to_stdout("--html"));
  if (!json_to_stdout) {
    out() << "held-out validation of " << printable(model_file) << " on " << printable(data_file)
          << ": " << v.configurations << " configurations, " << v.readings << " readings\n";
    // Repeats test the noise at their configurations, not the calibration elsewhere.
    if (loaded.repeated_configurations > 0)
      out() << "repeats: " << loaded.repeat_rows << " rows measure only "
            << loaded.repeated_configurations
            << " configuration(s) again: they test the noise and the prediction there, and "
               "the parameters' error is common to all of them (counted once by the test)\n";
    if (tested)
      out() << "predicted: noise = " << noise_source
            << (v.parameter_uncertainty
                    ? " + the parameters' uncertainty from the report (J Sigma J^T)"
                    : " alone (no --report: the parameters are taken as exact)")
            << "\n";
    else
      out() << "predicted: nothing (no --report and no reading_std in the model): the errors "
               "are reported, the consistency test is not made\n";
    for (const auto& p : v.per_reading) {
      if (!p.count) continue;
      if (tested)
        out() << format_text(
            "  %-12s %-4s %5d readings  RMS %-10.4g max %-10.4g predicted RMS %-10.4g "
            "(noise %.4g, parameters %.4g)\n",
            p.name.c_str(), p.unit.c_str(), p.count, p.rms, p.max, p.predicted_rms, p.noise_std,
            p.parameter_rms);
      else
        out() << format_text("  %-12s %-4s %5d readings  RMS %-10.4g max %-10.4g\n", p.name.c_str(),
                             p.unit.c_str(), p.count, p.rms, p.max);
    }
    if (position.computed) {
      out() << "3-D position error of the measured point, mm (" << position.after.points
            << " points):\n";
      if (!position.before_is.empty())
        out() << format_text("  before  mean %9.4g  RMS %9.4g  max %9.4g   (%s)\n",
                             position.before.mean, position.before.rms, position.before.max,
                             position.before_is.c_str());
      out() << format_text("  %-7s mean %9.4g  RMS %9.4g  max %9.4g   (%s)\n",
                           position.before_is.empty() ? "error" : "after", position.after.mean,
                           position.after.rms, position.after.max, model_file.c_str());
    }
    if (tested)
      out() << "standardized RMS " << format("%.3f", v.standardized_rms)
            << " (1 = as predicted), chi-square " << format("%.4g", v.chi_square) << " on "
            << v.readings << " degrees of freedom: P(larger) " << format("%.3g", v.p_larger)
            << ", P(smaller) " << format("%.3g", v.p_smaller) << "\n";
    if (v.verdict == "not_tested")
      out() << "not tested: give --report (the calibration's) or state reading_std in the "
               "model to test the residuals against a prediction\n";
    else if (v.verdict == "consistent")
      out() << "consistent: the held-out residuals are what the calibration predicts\n";
    else if (v.verdict == "larger_than_predicted")
      out() << "NOT consistent: the held-out residuals are larger than predicted (the "
               "model misses something, or its uncertainty is understated)\n";
    else
      out() << "smaller than predicted: the stated noise or uncertainty is pessimistic\n";
    if (!shows_pose) out() << "note: " << kPoseNotShown << "\n";
    if (target) out() << "target: " << target_result["verdict"].get<std::string>() << "\n";
  }
  if (vm.count("json") || vm.count("html")) {
    Json out;
    out["format"] = "kincal-validation";
    out["version"] = 1;
    out["model"] = model_file;
    out["data"] = data_file;
    out["report"] = vm.count("report") ? Json(vm["report"].as<std::string>()) : Json();
    out["configurations"] = v.configurations;
    out["readings"] = v.readings;
    out["skipped_lines"] = loaded.skipped_lines;
    out["dropped_readings"] = loaded.dropped_readings;
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
      errors["after_model"] = model_file;
      out["position_error_mm"] = errors;
    }
    out["duplicate_rows"] = loaded.duplicate_rows;
    out["repeated_configurations"] = loaded.repeated_configurations;
    out["repeat_rows"] = loaded.repeat_rows;
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
    if (target) out["target"] = target_result;
    Json residuals = Json::array();
    const auto names = model->reading_names();
    for (int c = 0; c < v.residuals.rows(); ++c) {
      Json row;
      row["line"] = loaded.lines[c];
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
    std::vector<std::pair<std::string, std::string>> outputs;
    if (vm.count("json")) outputs.push_back({"--json", out.dump(2) + "\n"});
    if (vm.count("html")) outputs.push_back({"--html", render_validation_html(out)});
    plan.write(outputs);
  }
  // As verify: a check that fails is exit code 1.
  return v.verdict == "larger_than_predicted" ? 1 : 0;
}

}  // namespace kincal::cli
