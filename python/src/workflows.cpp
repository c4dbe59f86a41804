// The calibrate and validate workflows (framework/workflows/) called from Python with typed
// arguments: a Model, measurements as arrays or a file, the options as values. No argv, no
// temporary file, no command-line parsing: the same library calls the program makes between
// parsing its options and writing its files, so the JSON is the program's for the same inputs.
// The outputs a caller asks for (out, json, html) are written as the program writes them:
// checked before the solve (none may be an input or another output), all or none after it.

#include <pybind11/stl.h>

#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "interrupt.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/html_pages.hpp"
#include "kincal/cli/html_report.hpp"
#include "kincal/cli/output_plan.hpp"
#include "kincal/cli/sha256.hpp"
#include "kincal/framework/base/parallel.hpp"
#include "kincal/framework/calibration/prior_and_noise.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/framework/workflows/calibrate_report.hpp"
#include "kincal/framework/workflows/report_prediction.hpp"
#include "kincal/framework/workflows/validate_report.hpp"
#include "kincal/models/model_io.hpp"
#include "model_handle.hpp"

namespace kincal::python {

namespace {

using Json = nlohmann::ordered_json;

// The measurements of a call: the file `path`, read and screened as the program does, or the
// arrays (already in the model's column order and units), screened the same way.
LoadedMeasurements measurements_for(const MeasurementModel& model, const VectorXd& values,
                                    const std::optional<std::string>& path,
                                    const py::object& actuators, const py::object& readings,
                                    bool skip_bad_rows, const std::string& model_name,
                                    std::string& data_name) {
  MeasurementLoadOptions options;
  options.skip_unreachable_rows = skip_bad_rows;
  options.model_file = model_name;
  if (path) {
    data_name = *path;
    py::gil_scoped_release release;
    return load_measurements(*path, model, values, options);
  }
  data_name = "measurements";
  const auto a = as_rows(actuators, "actuators", model.mechanism().num_actuators());
  const auto r = as_rows(readings, "readings", model.num_readings());
  if (a.shape(0) != r.shape(0))
    throw py::value_error("readings: expected " + std::to_string(a.shape(0)) +
                          " rows, one per row of actuators, got " + std::to_string(r.shape(0)));
  Measurements data;
  data.actuators = rows_view(a);
  data.readings = rows_view(r);
  py::gil_scoped_release release;
  return screen_measurements(table_in_memory(std::move(data)), model, values, options, data_name);
}

// The outputs asked for, checked before any work against the files read (`inputs`) and each
// other: labels are the keyword names.
cli::OutputPlan plan_outputs(const std::vector<std::string>& inputs,
                             const std::vector<std::pair<std::string, std::string>>& outputs) {
  cli::OutputPlan plan;
  for (const auto& path : inputs) plan.input("input", path);
  for (const auto& [label, path] : outputs)
    if (!path.empty()) plan.output(label, path == "-" ? "./-" : path);
  // "-" is a file here, not standard output: the check runs with a console of its own.
  const std::lock_guard<std::mutex> lock(command_mutex());
  std::ostringstream nothing;
  const cli::ConsoleScope console(nothing, nothing);
  plan.check();
  return plan;
}

// Writes (label, content) pairs as the program does (whole or not at all). The writer flushes
// the console: a console of its own here, as a command has.
void write_outputs(const cli::OutputPlan& plan,
                   const std::vector<std::pair<std::string, std::string>>& contents) {
  if (contents.empty()) return;
  py::gil_scoped_release release;
  const std::lock_guard<std::mutex> lock(command_mutex());
  std::ostringstream nothing;
  const cli::ConsoleScope console(nothing, nothing);
  plan.write(contents);
}

// The solver by name with its settings checked once, the robust loss among them.
void choose_solver(CalibrateRequest& request, const std::string& name, int max_iterations,
                   const std::map<std::string, std::string>& backend_options,
                   const std::string& loss, int threads, bool stop_on_sigint) {
  if (backend_options.count("loss"))
    throw std::invalid_argument("solver_options 'loss': give the robust loss as loss=\"" +
                                backend_options.at("loss") +
                                "\" (calibrate reports the loss and uses it for the standard "
                                "deviations)");
  request.solver = SolverRegistry::global().create(name);
  SolverOptions& options = request.solver_options;
  options.backend_options = backend_options;
  if (max_iterations < 1) throw std::invalid_argument("max_iterations must be at least 1");
  options.max_iterations = max_iterations;
  if (threads < 0 || threads > 1024) throw std::invalid_argument("threads must be from 0 to 1024");
  options.num_threads = threads == 0 ? hardware_threads() : threads;
  if (!loss.empty()) {
    try {
      request.loss = RobustLoss::parse(loss);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("loss '" + loss + "': " + e.what());
    }
    options.backend_options["loss"] = loss;
  }
  if (stop_on_sigint)
    options.callback = [](const IterationRecord&, const VectorXd&) {
      return sigint_received() ? CallbackAction::kStop : CallbackAction::kContinue;
    };
  request.solver->check_options(options);
}

// free, then fix: each pattern must match a parameter.
void apply_free_fix(MeasurementModel& model, const std::vector<std::string>& free,
                    const std::vector<std::string>& fix) {
  for (const auto& [patterns, value] : {std::pair{&free, true}, std::pair{&fix, false}})
    for (const std::string& pattern : *patterns) {
      try {
        model.parameters().set_free(pattern, value);
      } catch (const std::invalid_argument&) {
        throw std::invalid_argument(std::string(value ? "free" : "fix") + " '" + pattern +
                                    "': matches no parameter of the model");
      }
    }
}

void apply_noise_std(MeasurementModel& model, const std::string& noise_std) {
  if (noise_std.empty()) return;
  try {
    const VectorXd std = noise_std_per_reading(parse_non_negative_unit_values(noise_std), model);
    const std::vector<std::string> names = model.reading_names();
    for (int i = 0; i < model.num_readings(); ++i) model.set_reading_std(names[i], std[i]);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("noise_std '" + noise_std + "': " + e.what());
  }
}

void apply_prior_std(MeasurementModel& model, const std::vector<std::string>& specs) {
  for (const std::string& spec : specs) {
    try {
      kincal::apply_prior_std(parse_prior_std(spec), model);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("prior_std '" + spec + "': " + e.what());
    }
  }
}

// The calibrated model file's text: what this run estimated listed as free (a model written
// after allow_rank_deficient must not stop again on the parameters that had to be fixed).
std::string calibrated_model_text(MeasurementModel model, const CalibrateResult& result) {
  for (const auto& name : result.fixed_by_identifiability) model.parameters().set_free(name, false);
  return model_to_json(model, result.parameters).dump(2) + "\n";
}

py::dict calibrate_workflow(
    const ModelHandle& handle, const std::optional<std::string>& data_path,
    const py::object& actuators, const py::object& readings, const std::string& solver,
    int max_iterations, const std::map<std::string, std::string>& solver_options,
    const std::string& loss, const std::vector<std::string>& free,
    const std::vector<std::string>& fix, const std::vector<std::string>& prior_std,
    const std::string& noise_std, int folds, int starts, std::uint64_t seed, double rcond,
    bool allow_rank_deficient, const std::string& formulation, bool skip_bad_rows, int threads,
    const std::string& out, const std::string& json, const std::string& html,
    const std::string& model_path, const std::vector<std::string>& inputs, bool catch_sigint) {
  if (!(rcond > 0 && rcond < 1)) throw std::invalid_argument("rcond must be in (0, 1)");
  if (folds != 0 && folds < 2)
    throw std::invalid_argument("folds must be at least 2 (the number of cross-validation folds)");
  if (starts < 1) throw std::invalid_argument("starts must be at least 1");
  CalibrateRequest request;
  choose_solver(request, solver, max_iterations, solver_options, loss, threads, catch_sigint);
  const cli::OutputPlan plan = plan_outputs(inputs, {{"out", out}, {"json", json}, {"html", html}});

  auto model = std::make_shared<MeasurementModel>(*handle.model);
  apply_free_fix(*model, free, fix);
  apply_noise_std(*model, noise_std);
  apply_prior_std(*model, prior_std);
  request.model_file = model_path.empty() ? handle.source : model_path;
  check_calibration_model(*model, request.loss, request.model_file);
  request.measurements =
      measurements_for(*model, model->parameters().nominal_values(), data_path, actuators, readings,
                       skip_bad_rows, request.model_file, request.data_file);
  request.model = model;
  if (!formulation.empty()) request.formulation = parse_formulation(formulation);
  request.identifiability.rcond = rcond;
  request.when_rank_deficient =
      when_rank_deficient(*model, allow_rank_deficient, !free.empty() || !fix.empty());
  request.rank_deficiency_remedy =
      "fix parameters with fix=[...], or pass allow_rank_deficient=True";
  request.folds = folds;
  request.starts = starts;
  request.seed = seed;

  CalibrateResult result;
  bool interrupted = false;
  {
    py::gil_scoped_release release;
    SigintScope sigint(catch_sigint);
    result = calibrate(request);
    interrupted = sigint.interrupted();
  }
  Json report = calibration_json(result, Json::object());
  std::string model_text;
  if (result.solved && !out.empty()) {
    model_text = calibrated_model_text(*model, result);
    report["calibrated_model"] = {{"file", out}, {"sha256", cli::sha256_hex(model_text)}};
  } else {
    report["calibrated_model"] = nullptr;
  }
  std::vector<std::pair<std::string, std::string>> contents;
  if (!json.empty()) contents.push_back({"json", report.dump(2) + "\n"});
  if (!html.empty()) contents.push_back({"html", cli::render_calibration_html(report)});
  if (!model_text.empty()) contents.push_back({"out", model_text});
  write_outputs(plan, contents);

  py::dict answer;
  answer["report"] = report.dump();
  answer["text"] = calibration_text(result, "");
  answer["notes"] = result.notes;
  answer["solved"] = result.solved;
  answer["interrupted"] = interrupted;
  MeasurementModel calibrated = *model;
  for (const auto& name : result.fixed_by_identifiability)
    calibrated.parameters().set_free(name, false);
  answer["calibrated_model"] =
      result.solved ? py::cast(ModelHandle{model_with_values(calibrated, result.parameters),
                                           out.empty() ? handle.source : out})
                    : py::none();
  return answer;
}

py::dict validate_workflow(const ModelHandle& handle, const std::optional<std::string>& data_path,
                           const py::object& actuators, const py::object& readings,
                           const std::optional<std::string>& report_json,
                           const std::string& report_name, const std::optional<ModelHandle>& before,
                           const std::string& before_name, const std::string& noise_std,
                           bool skip_bad_rows, const std::string& json, const std::string& html,
                           const std::string& model_path, const std::vector<std::string>& inputs) {
  const cli::OutputPlan plan = plan_outputs(inputs, {{"json", json}, {"html", html}});

  const std::shared_ptr<const MeasurementModel> model = handle.model;
  const VectorXd values = model->parameters().nominal_values();
  ValidateRequest request;
  request.model_file = model_path.empty() ? handle.source : model_path;
  ReportPrediction report;
  if (report_json) {
    Json document;
    try {
      document = Json::parse(*report_json);
    } catch (const nlohmann::json::exception& e) {
      throw std::invalid_argument(report_name + ": not JSON (" + e.what() +
                                  "); expected a calibration report");
    }
    report = parse_report_prediction(document, report_name);
    if (!model_path.empty() && !report.calibrated_sha256.empty() &&
        cli::model_file_sha256(model_path) != report.calibrated_sha256)
      throw std::invalid_argument(model_path + " is not the calibrated model " + report_name +
                                  " describes (their SHA-256 differ); expected the model "
                                  "written with this report");
    request.prediction = prediction_from_report(report, *model, report_name, request.model_file);
  } else {
    request.prediction = prediction_from_model(*model);
  }
  if (!noise_std.empty()) {
    try {
      request.prediction.noise_std =
          noise_std_per_reading(parse_non_negative_unit_values(noise_std), *model);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("noise_std '" + noise_std + "': " + e.what());
    }
    request.prediction.noise_source = "noise_std";
  }
  if (before) {
    const auto& a = model->parameters();
    const auto& b = before->model->parameters();
    bool same = a.size() == b.size() && model->reading_names() == before->model->reading_names();
    for (int i = 0; same && i < a.size(); ++i) same = a[i].name == b[i].name;
    if (!same)
      throw std::invalid_argument(before_name + ": not the same parameters and readings as " +
                                  request.model_file +
                                  "; expected the model the calibration started from");
    request.before_values = b.nominal_values();
    request.before_is = before_name;
  } else if (report_json) {
    request.before_values = values_before_calibration(report, request.prediction, values);
    if (request.before_values)
      request.before_is = report_name + " (its parameters' nominal values)";
  }
  request.measurements = measurements_for(*model, values, data_path, actuators, readings,
                                          skip_bad_rows, request.model_file, request.data_file);
  request.model = model;
  ValidateResult result;
  {
    py::gil_scoped_release release;
    result = validate(request);
  }
  const Json out = validation_json(request, result, report_json ? report_name : "", Json());
  std::vector<std::pair<std::string, std::string>> contents;
  if (!json.empty()) contents.push_back({"json", out.dump(2) + "\n"});
  if (!html.empty()) contents.push_back({"html", cli::render_validation_html(out)});
  write_outputs(plan, contents);
  py::dict answer;
  answer["report"] = out.dump();
  answer["text"] = validation_text(request, result, request.model_file, request.data_file);
  answer["notes"] = result.notes;
  return answer;
}

}  // namespace

void bind_workflows(py::module_& m) {
  m.def("_calibrate", &calibrate_workflow, py::arg("model"), py::arg("data_path"),
        py::arg("actuators"), py::arg("readings"), py::arg("solver"), py::arg("max_iterations"),
        py::arg("solver_options"), py::arg("loss"), py::arg("free"), py::arg("fix"),
        py::arg("prior_std"), py::arg("noise_std"), py::arg("folds"), py::arg("starts"),
        py::arg("seed"), py::arg("rcond"), py::arg("allow_rank_deficient"), py::arg("formulation"),
        py::arg("skip_bad_rows"), py::arg("threads"), py::arg("out"), py::arg("json"),
        py::arg("html"), py::arg("model_path"), py::arg("inputs"), py::arg("catch_sigint"),
        "The calibrate workflow (kincal.calibrate is its face): a dict with the report's "
        "JSON text, the text report, the notes, solved, interrupted and the calibrated Model.");
  m.def("_validate", &validate_workflow, py::arg("model"), py::arg("data_path"),
        py::arg("actuators"), py::arg("readings"), py::arg("report_json"), py::arg("report_name"),
        py::arg("before"), py::arg("before_name"), py::arg("noise_std"), py::arg("skip_bad_rows"),
        py::arg("json"), py::arg("html"), py::arg("model_path"), py::arg("inputs"),
        "The validate workflow (kincal.validate is its face): a dict with the report's JSON "
        "text, the text report and the notes.");
}

}  // namespace kincal::python
