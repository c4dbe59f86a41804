// The calibrate and validate workflows (framework/workflows/), the export formats and the URDF
// import, called from Python with typed arguments: a Model, measurements as arrays or a file, the
// options as values. No argv, no temporary file, no command-line parsing: the same library calls
// the program makes between parsing its options and writing its files, so the JSON is the program's
// for the same inputs. The outputs a caller asks for (out, json, html) are written as the program
// writes them: checked before the solve (none may be an input or another output), all or none after
// it.

#include <pybind11/stl.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "interrupt.hpp"
#include "kincal/framework/analysis/target_accuracy.hpp"
#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/base/parallel.hpp"
#include "kincal/framework/calibration/measurement_file.hpp"
#include "kincal/framework/calibration/prior_and_noise.hpp"
#include "kincal/framework/io/json_input.hpp"
#include "kincal/framework/io/output_plan.hpp"
#include "kincal/framework/io/sha256.hpp"
#include "kincal/framework/kinematics/model_pair.hpp"
#include "kincal/framework/kinematics/names.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/framework/report/calibration_page.hpp"
#include "kincal/framework/report/pages.hpp"
#include "kincal/framework/workflows/calibrate_report.hpp"
#include "kincal/framework/workflows/compare.hpp"
#include "kincal/framework/workflows/design.hpp"
#include "kincal/framework/workflows/observability.hpp"
#include "kincal/framework/workflows/report_prediction.hpp"
#include "kincal/framework/workflows/simulate.hpp"
#include "kincal/framework/workflows/validate_report.hpp"
#include "kincal/models/camera_start.hpp"
#include "kincal/models/camera_views.hpp"
#include "kincal/models/export_formats.hpp"
#include "kincal/models/model_io.hpp"
#include "kincal/models/urdf_io.hpp"
#include "model_handle.hpp"
#if KINCAL_WITH_VISION
#include "kincal/vision/thumbnail.hpp"
#endif

namespace kincal::python {

namespace {

using Json = nlohmann::ordered_json;

// Each camera view drawn on its image for the page, when this module has OpenCV; what to tell
// the user ("" when nothing).
std::string draw_views_on_images(std::vector<ImageViews>& views, const std::string& folder) {
  bool named = false;
  for (const ImageViews& sensor : views)
    for (const ImageView& view : sensor.views) named = named || !view.image.empty();
  if (!named) return "";
#if KINCAL_WITH_VISION
  const std::string unread = vision::draw_views_on_images(views, folder);
  return unread.empty() ? "" : unread + " (images=DIR)";
#else
  (void)folder;
  return "the views are drawn without their images: this module was built without OpenCV";
#endif
}

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
  options.backend = request.solver->parse_settings(backend_options);
  if (max_iterations < 1) throw std::invalid_argument("max_iterations must be at least 1");
  options.max_iterations = max_iterations;
  if (threads < 0 || threads > 1024) throw std::invalid_argument("threads must be from 0 to 1024");
  options.num_threads = threads == 0 ? hardware_threads() : threads;
  if (stop_on_sigint)
    options.callback = [](const IterationRecord&, const VectorXd&) {
      return sigint_received() ? CallbackAction::kStop : CallbackAction::kContinue;
    };
  request.solver->check_options(options);
  if (!loss.empty())
    add_robust_loss(loss, *request.solver, name, options, "loss", "use solver=\"lm\"");
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

// target= (the program's --target): "" for none.
std::optional<TargetAccuracy> target_accuracy(const std::string& target) {
  if (target.empty()) return std::nullopt;
  return parse_target_accuracy(target, "target");
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
    const std::string& model_path, const std::vector<std::string>& inputs, bool catch_sigint,
    const std::string& tolerance_priors, const std::string& images,
    const std::vector<std::string>& steps, const std::string& target) {
  const std::optional<TargetAccuracy> accuracy = target_accuracy(target);
  if (!(rcond > 0 && rcond < 1)) throw std::invalid_argument("rcond must be in (0, 1)");
  if (folds != 0 && folds < 2)
    throw std::invalid_argument("folds must be at least 2 (the number of cross-validation folds)");
  if (starts < 1) throw std::invalid_argument("starts must be at least 1");
  CalibrateRequest request;
  choose_solver(request, solver, max_iterations, solver_options, loss, threads, catch_sigint);
  const OutputPlan plan = plan_outputs(inputs, {{"out", out}, {"json", json}, {"html", html}});

  auto model = std::make_shared<MeasurementModel>(*handle.model);
  apply_free_fix(*model, free, fix);
  apply_noise_std(*model, noise_std);
  apply_prior_std(*model, prior_std);
  request.model_file = model_path.empty() ? handle.source : model_path;
  check_calibration_model(*model, request.solver_options.loss, request.model_file);
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
  request.tolerance_priors = parse_tolerance_priors(tolerance_priors, "tolerance_priors");
  for (const std::string& text : steps)
    request.steps.push_back(parse_calibration_step(text, "steps"));

  CalibrateResult result;
  bool interrupted = false;
  {
    py::gil_scoped_release release;
    SigintScope sigint(catch_sigint);
    result = calibrate(request);
    interrupted = sigint.interrupted();
  }
  // A camera's views: their reprojection error, and each against the pose its points alone
  // give, as the program adds them.
  Json extra = Json::object();
  std::string extra_text;
  kincal::report::CalibrationPageExtras page;
  std::vector<std::string> notes = result.notes;
  if (accuracy) {  // as the program: the judgement before a camera's views
    page.target = judge_calibration_target(result, *accuracy);
    extra["target"] = to_json(*page.target);
    extra_text += "target: " + page.target->verdict + "\n";
  }
  if (result.solved && has_camera(*model)) {
    CameraViewChecks views = calibration_camera_views(*model, result.parameters,
                                                      request.measurements, request.data_file);
    extra_text += views.text;
    extra["camera_views"] = views.views_json;
    extra["view_checks"] = views.json;
    if (!html.empty()) {
      const std::string folder =
          !images.empty() ? images
                          : std::filesystem::path(request.data_file).parent_path().string();
      const std::string said = draw_views_on_images(views.views, folder);
      if (!said.empty()) notes.push_back(said);
    }
    page.image_views = std::move(views.views);
  }
  Json report = calibration_json(result, extra);
  std::string model_text;
  if (result.solved && !out.empty()) {
    model_text = calibrated_model_text(*model, result.parameters, result.fixed_by_identifiability);
    page.calibrated_model_file = out;
    page.calibrated_model_sha256 = sha256_hex(model_text);
    report["calibrated_model"] = {{"file", out}, {"sha256", page.calibrated_model_sha256}};
  } else {
    report["calibrated_model"] = nullptr;
  }
  std::vector<std::pair<std::string, std::string>> contents;
  if (!json.empty()) contents.push_back({"json", report_json_text(report)});
  if (!html.empty()) contents.push_back({"html", kincal::report::calibration_html(result, page)});
  if (!model_text.empty()) contents.push_back({"out", model_text});
  write_outputs(plan, contents);

  py::dict answer;
  answer["report"] = report.dump();
  answer["text"] = calibration_text(result, extra_text);
  answer["notes"] = notes;
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
                           const std::string& model_path, const std::vector<std::string>& inputs,
                           const std::string& target) {
  const std::optional<TargetAccuracy> accuracy = target_accuracy(target);
  const OutputPlan plan = plan_outputs(inputs, {{"json", json}, {"html", html}});

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
        model_file_sha256(model_path) != report.calibrated_sha256)
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
  const PositionComparison& position = result.position;
  const std::optional<TargetJudgement> judged =
      accuracy ? std::optional<TargetJudgement>(judge_measured_target(
                     *accuracy, position.computed ? &position.after : nullptr,
                     "these held-out readings measure no point of the mechanism"))
               : std::nullopt;
  const Json out = validation_json(request, result, report_json ? report_name : "",
                                   judged ? to_json(*judged) : Json());
  std::vector<std::pair<std::string, std::string>> contents;
  if (!json.empty()) contents.push_back({"json", report_json_text(out)});
  if (!html.empty())
    contents.push_back({"html", kincal::report::validation_html(
                                    request, result, report_json ? report_name : "", judged)});
  write_outputs(plan, contents);
  py::dict answer;
  answer["report"] = out.dump();
  answer["text"] = validation_text(request, result, request.model_file, request.data_file) +
                   (judged ? "target: " + judged->verdict + "\n" : std::string());
  answer["notes"] = result.notes;
  return answer;
}

py::dict observability_workflow(
    const ModelHandle& handle, const std::optional<std::string>& data_path,
    const py::object& actuators, const py::object& readings, int poses, std::uint64_t seed,
    double rcond, const std::string& config_range, const std::vector<std::string>& free,
    const std::vector<std::string>& fix, const std::vector<std::string>& prior_std,
    const std::string& noise_std, bool skip_bad_rows, const std::string& json,
    const std::string& html, const std::string& model_path,
    const std::vector<std::string>& inputs) {
  const bool from_data = data_path || !actuators.is_none();
  if (from_data == (poses > 0))
    throw std::invalid_argument(
        "give exactly one of data and poses (a number of random "
        "configurations, at least 1)");
  if (!(rcond > 0 && rcond < 1)) throw std::invalid_argument("rcond must be in (0, 1)");
  const OutputPlan plan = plan_outputs(inputs, {{"json", json}, {"html", html}});
  auto model = std::make_shared<MeasurementModel>(*handle.model);
  apply_free_fix(*model, free, fix);
  apply_noise_std(*model, noise_std);
  apply_prior_std(*model, prior_std);
  ObservabilityRequest request;
  request.model_file = model_path.empty() ? handle.source : model_path;
  request.identifiability.rcond = rcond;
  request.explicit_mask = !free.empty() || !fix.empty();
  if (from_data) {
    request.data =
        measurements_for(*model, model->parameters().nominal_values(), data_path, actuators,
                         readings, skip_bad_rows, request.model_file, request.source)
            .data;
  } else {
    UnitValues range;
    if (!config_range.empty()) {
      try {
        range = parse_non_negative_unit_values(config_range);
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument("config_range '" + config_range + "': " + e.what());
      }
    }
    py::gil_scoped_release release;
    request.data = random_configurations(*model, poses, seed, range);
    request.source = std::to_string(request.data.size()) + " random configurations";
  }
  request.model = model;
  ObservabilityResult result;
  {
    py::gil_scoped_release release;
    result = observe(request);
  }
  const Json out = observability_json(result, Json::object());
  std::vector<std::pair<std::string, std::string>> contents;
  if (!json.empty()) contents.push_back({"json", report_json_text(out)});
  if (!html.empty()) contents.push_back({"html", kincal::report::observability_html(result)});
  write_outputs(plan, contents);
  py::dict answer;
  answer["report"] = out.dump();
  answer["text"] = observability_text(result);
  return answer;
}

py::dict compare_workflow(const ModelHandle& truth, const ModelHandle& handle,
                          const std::optional<std::string>& data_path, const py::object& actuators,
                          int poses, std::uint64_t seed, const std::string& json,
                          const std::string& html, const std::string& truth_path,
                          const std::string& model_path, const std::vector<std::string>& inputs) {
  const OutputPlan plan = plan_outputs(inputs, {{"json", json}, {"html", html}});
  CompareRequest request;
  request.truth = truth.model;
  request.model = handle.model;
  request.truth_file = truth_path.empty() ? truth.source : truth_path;
  request.model_file = model_path.empty() ? handle.source : model_path;
  request.workspace_poses = poses;
  request.seed = seed;
  if (data_path) {
    request.data_file = *data_path;
    py::gil_scoped_release release;  // the file may be a FIFO another Python thread writes
    request.configurations =
        read_model_columns(*data_path, *handle.model, CsvLimits{}).data.actuators;
  } else if (!actuators.is_none()) {
    request.data_file = "measurements";
    const auto a = as_rows(actuators, "actuators", handle.model->mechanism().num_actuators());
    request.configurations = rows_view(a);
    if (request.configurations.rows() == 0)
      throw std::invalid_argument("data: no configuration to compare the poses at");
  }
  CompareResult result;
  {
    py::gil_scoped_release release;
    result = compare_models(request);
  }
  const Json out = comparison_json(result);
  std::vector<std::pair<std::string, std::string>> contents;
  if (!json.empty()) contents.push_back({"json", report_json_text(out)});
  if (!html.empty()) contents.push_back({"html", kincal::report::compare_html(result)});
  write_outputs(plan, contents);
  py::dict answer;
  answer["report"] = out.dump();
  answer["text"] = comparison_text(result);
  return answer;
}

py::dict simulate_workflow(const ModelHandle& handle, const std::string& model_name, int case_id,
                           std::optional<int> poses, std::optional<std::string> noise_half_width,
                           std::optional<std::string> noise_std, const std::string& param_error,
                           std::optional<std::string> config_range, std::uint64_t seed,
                           int validation, const std::string& solver, int max_iterations,
                           const std::map<std::string, std::string>& solver_options, int threads,
                           const std::string& formulation, const std::string& design,
                           int design_candidates, const std::vector<std::string>& prior_std,
                           const std::optional<std::string>& configs_path,
                           const py::object& configs_actuators, const py::object& configs_readings,
                           const std::optional<ModelHandle>& truth, const std::string& truth_name,
                           const std::string& write_data, bool allow_rank_deficient, int starts,
                           const std::string& json, const std::string& trace,
                           const std::vector<std::string>& inputs, bool catch_sigint) {
  ScenarioText text;
  text.case_id = case_id;
  text.poses = poses;
  text.noise_half_width = std::move(noise_half_width);
  text.noise_std = std::move(noise_std);
  text.param_error = param_error;
  text.config_range = std::move(config_range);
  text.seed = seed;
  text.validation = validation;
  ScenarioOptions scenario = scenario_options(text, "");
  const bool configs_given = configs_path || !configs_actuators.is_none();
  if (configs_given && (poses || case_id != 0 || !design.empty()))
    throw std::invalid_argument(
        "configs gives the configurations: give it without poses, case and design");
  if (truth && param_error != "5mm,0.01rad")
    throw std::invalid_argument("truth gives the true model: give it without param_error");
  if (starts < 1) throw std::invalid_argument("starts must be at least 1");
  // Priors per unit only are the scenario's (every free parameter of a unit); with a
  // pattern they are set on the model itself.
  std::vector<PriorStdRule> rules;
  for (const std::string& spec : prior_std) {
    try {
      for (const PriorStdRule& rule : parse_prior_std(spec)) rules.push_back(rule);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("prior_std '" + spec + "': " + e.what());
    }
  }
  auto model = std::make_shared<MeasurementModel>(*handle.model);
  if (!rules.empty() && prior_std_per_unit_only(rules)) {
    UnitValues per_unit;
    for (const PriorStdRule& rule : rules) per_unit.set(rule.unit, rule.value);
    scenario.prior_std = per_unit;
  } else if (!rules.empty()) {
    try {
      kincal::apply_prior_std(rules, *model);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("prior_std: ") + e.what());
    }
  }
  std::string truth_file;
  std::vector<std::pair<std::string, std::string>> outputs = {{"json", json}, {"trace", trace}};
  if (!write_data.empty()) {
    if (write_data == "-")
      throw std::invalid_argument("write_data needs a file name (it writes two files)");
    truth_file = std::filesystem::path(write_data).replace_extension(".truth.json").string();
    outputs.push_back({"write_data", write_data});
    outputs.push_back({"write_data's true model", truth_file});
  }
  const OutputPlan plan = plan_outputs(inputs, outputs);

  SimulateRequest request;
  if (truth) {
    check_same_parameters(*truth->model, "truth " + printable(truth_name), *model,
                          "the model " + printable(model_name));
    scenario.truth = truth->model->parameters().nominal_values();
    request.truth_file = truth_name;
  }
  if (configs_path) {
    request.configs_file = *configs_path;
    py::gil_scoped_release release;  // the file may be a FIFO another Python thread writes
    scenario.planned = planned_rows(read_model_columns(*configs_path, *model, CsvLimits{}).data);
    scenario.num_configurations = scenario.planned.size();
  } else if (!configs_actuators.is_none()) {
    request.configs_file = "measurements";
    const auto a = as_rows(configs_actuators, "actuators", model->mechanism().num_actuators());
    const auto r = as_rows(configs_readings, "readings", model->num_readings());
    Measurements rows;
    rows.actuators = rows_view(a);
    rows.readings = rows_view(r);
    scenario.planned = planned_rows(std::move(rows));
    scenario.num_configurations = scenario.planned.size();
  }
  if (!design.empty()) request.design = parse_design_criterion(design);
  request.design_candidates = design_candidates;
  CalibrateRequest solver_choice;  // the solver and its settings, checked as calibrate's
  choose_solver(solver_choice, solver, max_iterations, solver_options, "", threads, catch_sigint);
  request.solver = solver_choice.solver;
  request.solver_options = solver_choice.solver_options;
  if (!formulation.empty()) request.formulation = parse_formulation(formulation);
  request.model = model;
  request.scenario = scenario;
  request.starts = starts;
  request.allow_rank_deficient = allow_rank_deficient;
  request.model_name = model_name;
  request.case_id = case_id;
  request.option_prefix = "";
  request.priors_given = !rules.empty();
  request.rank_deficiency_remedy =
      "widen config_range, measure more poses, fix parameters (the model's free list), or "
      "pass allow_rank_deficient=True";
  SimulateResult result;
  bool interrupted = false;
  {
    py::gil_scoped_release release;
    SigintScope sigint(catch_sigint);
    result = simulate(request);
    interrupted = sigint.interrupted();
  }
  const nlohmann::json report = simulation_json(result);
  std::vector<std::pair<std::string, std::string>> contents;
  if (!json.empty()) contents.push_back({"json", report_json_text(report)});
  if (!trace.empty()) contents.push_back({"trace", simulation_trace_csv(result.run)});
  if (!write_data.empty()) {
    const std::string truth_text = model_to_json(*model, result.scenario.truth).dump(2) + "\n";
    contents.push_back({"write_data's true model", truth_text});
    contents.push_back({"write_data", simulated_data_csv(result, truth_file, truth_text)});
  }
  write_outputs(plan, contents);
  py::dict answer;
  answer["report"] = report.dump();
  answer["text"] = simulation_text(result);
  answer["notes"] = result.notes;
  answer["solved"] = result.solved;
  answer["interrupted"] = interrupted;
  return answer;
}

py::dict design_workflow(const ModelHandle& handle, int count, const std::string& criterion,
                         int candidates, std::uint64_t seed, double singularity_margin,
                         const std::string& orientation_length, const std::string& config_range,
                         const std::vector<std::string>& free, const std::vector<std::string>& fix,
                         const std::vector<std::string>& prior_std, const std::string& noise_std,
                         const std::optional<std::string>& existing_path,
                         const py::object& existing_actuators, const py::object& existing_readings,
                         bool bound, const std::string& out, const std::string& json,
                         const std::string& html, const std::string& model_path,
                         const std::vector<std::string>& inputs, bool catch_sigint,
                         const py::object& within, const py::object& candidate_configurations,
                         const py::object& centre, const std::string& target) {
  const std::optional<TargetAccuracy> accuracy = target_accuracy(target);
  ExperimentDesignRequest request;
  DesignOptions& design = request.options;
  const py::ssize_t na = handle.model->mechanism().num_actuators();
  if (!within.is_none() && !candidate_configurations.is_none())
    throw std::invalid_argument("give within or candidate_configurations, not both");
  // Rows of configurations, or a CSV file of them (str: the face passes paths as str).
  auto configurations = [&](const py::object& value, const char* name) -> MatrixXd {
    if (py::isinstance<py::str>(value)) {
      try {
        return read_configurations(value.cast<std::string>(), *handle.model);
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string(name) + ": " + e.what());
      }
    }
    const auto rows = as_rows(value, name, na);
    if (rows.shape(0) == 0) throw std::invalid_argument(std::string(name) + ": no configuration");
    return rows_view(rows);
  };
  if (!within.is_none()) {
    const MatrixXd q = configurations(within, "within");
    design.box_low = q.colwise().minCoeff().transpose();
    design.box_high = q.colwise().maxCoeff().transpose();
  }
  if (!candidate_configurations.is_none())
    design.given = configurations(candidate_configurations, "candidate_configurations");
  if (!centre.is_none()) {
    if (!within.is_none() || !candidate_configurations.is_none())
      throw std::invalid_argument(
          "give one of within, candidate_configurations and centre, not several");
    const auto values = as_vector(centre, "centre", na);
    design.centre = Eigen::Map<const VectorXd>(values.data(), na);
  }
  design.count = count;
  design.num_random = candidates;
  design.seed = seed;
  design.min_singularity_margin = singularity_margin;
  try {
    design.criterion = parse_design_criterion(criterion);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("criterion: ") + e.what());
  }
  if (!(singularity_margin >= 0)) throw std::invalid_argument("singularity_margin must be >= 0");
  if (!orientation_length.empty()) {
    if (design.criterion != DesignCriterion::kI)
      throw std::invalid_argument("orientation_length applies to criterion I only");
    UnitValues length;
    try {
      length = parse_non_negative_unit_values(orientation_length);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("orientation_length '" + orientation_length + "': " + e.what());
    }
    if (length.values().size() != 1 || !length.has(kMillimetre) ||
        !std::isfinite(length.get(kMillimetre)))
      throw std::invalid_argument("orientation_length '" + orientation_length +
                                  "': expected a finite length, e.g. 300mm");
    design.orientation_length = length.get(kMillimetre);
  }
  const OutputPlan plan = plan_outputs(inputs, {{"out", out}, {"json", json}, {"html", html}});
  auto model = std::make_shared<MeasurementModel>(*handle.model);
  apply_free_fix(*model, free, fix);
  apply_prior_std(*model, prior_std);
  if (!config_range.empty()) {
    UnitValues range;
    try {
      range = parse_non_negative_unit_values(config_range);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("config_range '" + config_range + "': " + e.what());
    }
    for (const Actuator& a : model->mechanism().actuators())
      if (range.has(a.unit)) model->set_actuator_range(a.name, range.get(a.unit));
  }
  request.model_file = model_path.empty() ? handle.source : model_path;
  if (!noise_std.empty()) {
    try {
      request.noise_std = noise_std_per_reading(parse_non_negative_unit_values(noise_std), *model);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("noise_std '" + noise_std + "': " + e.what());
    }
    request.noise_source = "noise_std";
  }
  if (existing_path || !existing_actuators.is_none()) {
    std::string name;
    request.existing =
        measurements_for(*model, model->parameters().nominal_values(), existing_path,
                         existing_actuators, existing_readings, false, request.model_file, name)
            .data;
  }
  if (catch_sigint) design.monitor = [](const DesignStep&) { return !sigint_received(); };
  request.model = model;
  request.bound = bound;
  request.option_prefix = "";
  request.when_rank_deficient = when_rank_deficient(*model, false, !free.empty() || !fix.empty());
  ExperimentDesignResult result;
  bool interrupted = false;
  {
    py::gil_scoped_release release;
    SigintScope sigint(catch_sigint);
    result = design_experiment(request);
    interrupted = sigint.interrupted();
  }
  py::dict answer;
  answer["interrupted"] = interrupted;
  answer["stopped_before_design"] = result.stopped_before_design;
  answer["notes"] = result.notes;
  if (result.stopped_before_design) return answer;
  const std::optional<TargetJudgement> judged =
      accuracy
          ? std::optional<TargetJudgement>(judge_predicted_target(*accuracy, result.designed_pose))
          : std::nullopt;
  const Json report = design_json(result, out, judged ? to_json(*judged) : Json());
  std::vector<std::pair<std::string, std::string>> contents;
  if (!json.empty()) contents.push_back({"json", report_json_text(report)});
  if (!html.empty()) contents.push_back({"html", kincal::report::design_html(result, out, judged)});
  if (!out.empty()) contents.push_back({"out", design_template_csv(result)});
  write_outputs(plan, contents);
  answer["report"] = report.dump();
  answer["text"] =
      design_text(result, out) + (judged ? "target: " + judged->verdict + "\n" : std::string());
  answer["configurations"] = to_numpy(result.rows.actuators);
  return answer;
}

// The model in `format` (export_model). A model file is named with the SHA-256 of its bytes,
// as the program does; a Model in memory with that of its JSON as Model.to_json writes it.
std::string export_workflow(const ModelHandle& handle, const std::string& format,
                            const std::string& model_path, const std::string& out) {
  const OutputPlan plan = plan_outputs(
      model_path.empty() ? std::vector<std::string>{} : std::vector{model_path}, {{"out", out}});
  ExportSource source;
  source.model_file = model_path.empty() ? handle.source : model_path;
  source.sha256 =
      model_path.empty()
          ? sha256_hex(
                model_to_json(*handle.model, handle.model->parameters().nominal_values()).dump(2) +
                "\n")
          : model_file_sha256(model_path);
  std::string text;
  try {
    text = export_model(*handle.model, format, source);
  } catch (const ExportError& e) {
    throw std::invalid_argument(source.model_file + ": " + e.what());
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument(source.model_file + ": cannot be written as JSON (" + e.what() +
                                ")");
  }
  if (!out.empty()) write_outputs(plan, {{"out", text}});
  return text;
}

// A model of the arm in a URDF file with one tracker (model_from_urdf).
ModelHandle urdf_model(const std::string& path, const std::string& tip, const std::string& base,
                       const std::string& sensor, const std::vector<double>& point,
                       const std::string& compliance, bool payload_column,
                       const std::vector<double>& payload_centre, const std::vector<double>& frame,
                       const std::vector<double>& target) {
  UrdfModelOptions options;
  // Frames as a person writes them: mm and Z-Y-X angles in degrees (the CLI's --frame).
  const auto frame_of = [](const std::vector<double>& v, const char* name) {
    if (v.size() != 6)
      throw std::invalid_argument(std::string(name) + ": expected x, y, z (mm), rx, ry, rz (deg)");
    Vector6d f;
    f << v[0], v[1], v[2], v[3] * kRadiansPerDegree, v[4] * kRadiansPerDegree,
        v[5] * kRadiansPerDegree;
    return f;
  };
  if (!frame.empty()) options.frame = frame_of(frame, "frame");
  if (!target.empty()) options.target = frame_of(target, "target");
  if (compliance == "auto")
    options.compliance = UrdfCompliance::kAuto;
  else if (compliance == "urdf")
    options.compliance = UrdfCompliance::kInertials;
  else if (compliance == "fitted")
    options.compliance = UrdfCompliance::kFitted;
  else if (!compliance.empty())
    throw std::invalid_argument("compliance '" + compliance +
                                "': expected \"auto\", \"urdf\" or \"fitted\"");
  if ((payload_column || !payload_centre.empty()) && options.compliance == UrdfCompliance::kNone)
    throw std::invalid_argument("payload_column and payload_centre need compliance");
  options.payload_column = payload_column;
  if (!payload_centre.empty()) {
    if (payload_centre.size() != 3)
      throw std::invalid_argument("payload_centre: expected x, y, z in mm");
    options.payload_centre = Vector3d(payload_centre[0], payload_centre[1], payload_centre[2]);
  }
  options.tip_link = tip;
  options.base_link = base;
  options.sensor = sensor;
  if (!point.empty()) {
    if (point.size() != 3) throw std::invalid_argument("point: expected x, y, z in mm");
    options.point = Vector3d(point[0], point[1], point[2]);
  }
  std::string text;
  {
    py::gil_scoped_release release;  // the file may be a FIFO another Python thread writes
    text = read_file_text(path, "URDF", kMaxUrdfBytes);
  }
  try {
    return ModelHandle{model_from_urdf(text, is_valid_utf8(path) ? path : printable(path), options),
                       path};
  } catch (const UrdfError& e) {
    throw std::invalid_argument(path + ": " + e.what());
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ": " + e.what());
  }
}

}  // namespace

// The outputs asked for, checked before any work against the files read (`inputs`) and each
// other: labels are the keyword names. "-" is a file here, not standard output, and the
// module prints nothing: its standard output is a stream of its own (python_output()).
OutputPlan plan_outputs(const std::vector<std::string>& inputs,
                        const std::vector<std::pair<std::string, std::string>>& outputs) {
  OutputPlan plan(python_output());
  for (const auto& path : inputs) plan.input("input", path);
  for (const auto& [label, path] : outputs)
    if (!path.empty()) plan.output(label, path == "-" ? "./-" : path);
  plan.check();
  return plan;
}

// Writes (label, content) pairs as the program does (whole or not at all).
void write_outputs(const OutputPlan& plan,
                   const std::vector<std::pair<std::string, std::string>>& contents) {
  if (contents.empty()) return;
  py::gil_scoped_release release;
  plan.write(contents);
}

const StandardOutput& python_output() {
  // One per thread: a call writes its files with the GIL released.
  thread_local std::ostringstream nothing;
  thread_local const StreamOutput output(nothing);
  return output;
}

void bind_workflows(py::module_& m) {
  m.def("_observability", &observability_workflow, py::arg("model"), py::arg("data_path"),
        py::arg("actuators"), py::arg("readings"), py::arg("poses"), py::arg("seed"),
        py::arg("rcond"), py::arg("config_range"), py::arg("free"), py::arg("fix"),
        py::arg("prior_std"), py::arg("noise_std"), py::arg("skip_bad_rows"), py::arg("json"),
        py::arg("html"), py::arg("model_path"), py::arg("inputs"),
        "The observability workflow (kincal.observability is its face): a dict with the "
        "report's JSON text and the text report.");
  m.def("_compare", &compare_workflow, py::arg("truth"), py::arg("model"), py::arg("data_path"),
        py::arg("actuators"), py::arg("poses"), py::arg("seed"), py::arg("json"), py::arg("html"),
        py::arg("truth_path"), py::arg("model_path"), py::arg("inputs"),
        "The compare workflow (kincal.compare is its face): a dict with the report's JSON "
        "text and the text report.");
  m.def("_simulate", &simulate_workflow, py::arg("model"), py::arg("model_name"),
        py::arg("case_id"), py::arg("poses"), py::arg("noise_half_width"), py::arg("noise_std"),
        py::arg("param_error"), py::arg("config_range"), py::arg("seed"), py::arg("validation"),
        py::arg("solver"), py::arg("max_iterations"), py::arg("solver_options"), py::arg("threads"),
        py::arg("formulation"), py::arg("design"), py::arg("design_candidates"),
        py::arg("prior_std"), py::arg("configs_path"), py::arg("configs_actuators"),
        py::arg("configs_readings"), py::arg("truth"), py::arg("truth_name"), py::arg("write_data"),
        py::arg("allow_rank_deficient"), py::arg("starts"), py::arg("json"), py::arg("trace"),
        py::arg("inputs"), py::arg("catch_sigint"),
        "The simulate workflow (kincal.simulate is its face): a dict with the report's JSON "
        "text, the text report, the notes, solved and interrupted.");
  m.def("_design", &design_workflow, py::arg("model"), py::arg("count"), py::arg("criterion"),
        py::arg("candidates"), py::arg("seed"), py::arg("singularity_margin"),
        py::arg("orientation_length"), py::arg("config_range"), py::arg("free"), py::arg("fix"),
        py::arg("prior_std"), py::arg("noise_std"), py::arg("existing_path"),
        py::arg("existing_actuators"), py::arg("existing_readings"), py::arg("bound"),
        py::arg("out"), py::arg("json"), py::arg("html"), py::arg("model_path"), py::arg("inputs"),
        py::arg("catch_sigint"), py::arg("within"), py::arg("candidate_configurations"),
        py::arg("centre"), py::arg("target"),
        "The design workflow (kincal.design is its face): a dict with the report's JSON text, "
        "the text report, the notes, the configurations chosen and whether it was "
        "interrupted.");
  m.def("_export", &export_workflow, py::arg("model"), py::arg("format"), py::arg("model_path"),
        py::arg("out"),
        "The model in a controller's format (kincal.export is its face); writes `out` when "
        "given, and returns the text.");
  m.def("_model_from_urdf", &urdf_model, py::arg("path"), py::arg("tip"), py::arg("base"),
        py::arg("sensor"), py::arg("point"), py::arg("compliance"), py::arg("payload_column"),
        py::arg("payload_centre"), py::arg("frame"), py::arg("target"),
        "A model imported from a URDF file (kincal.model_from_urdf is its face).");
  m.def("_calibrate", &calibrate_workflow, py::arg("model"), py::arg("data_path"),
        py::arg("actuators"), py::arg("readings"), py::arg("solver"), py::arg("max_iterations"),
        py::arg("solver_options"), py::arg("loss"), py::arg("free"), py::arg("fix"),
        py::arg("prior_std"), py::arg("noise_std"), py::arg("folds"), py::arg("starts"),
        py::arg("seed"), py::arg("rcond"), py::arg("allow_rank_deficient"), py::arg("formulation"),
        py::arg("skip_bad_rows"), py::arg("threads"), py::arg("out"), py::arg("json"),
        py::arg("html"), py::arg("model_path"), py::arg("inputs"), py::arg("catch_sigint"),
        py::arg("tolerance_priors"), py::arg("images"), py::arg("steps"), py::arg("target"),
        "The calibrate workflow (kincal.calibrate is its face): a dict with the report's "
        "JSON text, the text report, the notes, solved, interrupted and the calibrated Model.");
  m.def("_validate", &validate_workflow, py::arg("model"), py::arg("data_path"),
        py::arg("actuators"), py::arg("readings"), py::arg("report_json"), py::arg("report_name"),
        py::arg("before"), py::arg("before_name"), py::arg("noise_std"), py::arg("skip_bad_rows"),
        py::arg("json"), py::arg("html"), py::arg("model_path"), py::arg("inputs"),
        py::arg("target"),
        "The validate workflow (kincal.validate is its face): a dict with the report's JSON "
        "text, the text report and the notes.");
}

}  // namespace kincal::python
