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
#include "kincal/cli/memory_check.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/cli/project_record.hpp"
#include "kincal/cli/shared_options.hpp"
#include "kincal/cli/target_accuracy.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/io/json_input.hpp"
#include "kincal/framework/io/sha256.hpp"
#include "kincal/framework/report/pages.hpp"
#include "kincal/framework/workflows/report_prediction.hpp"
#include "kincal/framework/workflows/validate_report.hpp"
#include "kincal/models/model_io.hpp"

namespace kincal::cli {

namespace {

using Json = nlohmann::ordered_json;

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
  OutputPlan plan(console_output());
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
    report = read_report_prediction(report_file);
    check_report_is_for_model(report_file, report.calibrated_sha256, model_file);
    prediction = prediction_from_report(report, *model, report_file, model_file);
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
  } else if (vm.count("report")) {
    request.before_values = values_before_calibration(report, prediction, values);
    if (request.before_values)
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
  const PositionComparison& position = result.position;
  const std::optional<TargetJudgement> judged =
      target ? std::optional<TargetJudgement>(judge_measured_target(
                   *target, position.computed ? &position.after : nullptr,
                   "these held-out readings measure no point of the mechanism"))
             : std::nullopt;
  const Json target_result = judged ? to_json(*judged) : Json();
  const bool json_to_stdout = (vm.count("json") && plan.to_stdout("--json")) ||
                              (vm.count("html") && plan.to_stdout("--html"));
  if (!json_to_stdout) {
    out() << validation_text(request, result, printable(model_file), printable(data_file));
    if (judged) out() << "target: " << judged->verdict << "\n";
  }
  if (vm.count("json") || vm.count("html")) {
    const Json out = validation_json(
        request, result, vm.count("report") ? vm["report"].as<std::string>() : "", target_result);
    std::vector<std::pair<std::string, std::string>> outputs;
    if (vm.count("json")) outputs.push_back({"--json", json_report_text(out)});
    if (vm.count("html"))
      outputs.push_back(
          {"--html",
           report::validation_html(
               request, result, vm.count("report") ? vm["report"].as<std::string>() : "", judged)});
    plan.write(outputs);
  }
  // As verify: a check that fails is exit code 1.
  return result.validation.verdict == "larger_than_predicted" ? 1 : 0;
}

}  // namespace kincal::cli
