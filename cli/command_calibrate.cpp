// kincal calibrate: estimates a model's free parameters from a measurement file and writes
// the calibrated model (same schema) and a report with uncertainty and identifiability.

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/memory_check.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/cli/project_record.hpp"
#include "kincal/cli/sensitivity_option.hpp"
#include "kincal/cli/shared_options.hpp"
#include "kincal/cli/starts_option.hpp"
#include "kincal/cli/target_accuracy.hpp"
#include "kincal/framework/io/sha256.hpp"
#include "kincal/framework/report/calibration_page.hpp"
#include "kincal/framework/workflows/calibrate_report.hpp"
#include "kincal/models/camera_start.hpp"
#include "kincal/models/camera_views.hpp"
#include "kincal/models/model_io.hpp"
#if KINCAL_WITH_VISION
#include "kincal/vision/thumbnail.hpp"
#endif

namespace kincal::cli {

namespace {

// The files of this run: no output may be an input or the other output. Checked before
// the data is read, so a typo does not cost a solve.
OutputPlan plan_files(const po::variables_map& vm) {
  OutputPlan plan(console_output());
  for (const char* option : {"model", "data"})
    if (vm.count(option)) plan.input(std::string("--") + option, vm[option].as<std::string>());
  if (vm.count("out")) plan.output("--out", vm["out"].as<std::string>());
  const std::string report = json_output(vm);
  if (!report.empty()) plan.output("--json", report);
  if (vm.count("html")) plan.output("--html", vm["html"].as<std::string>());
  plan.check();
  return plan;
}

// Each camera view drawn on its image (the page for people), when OpenCV can read them.
void draw_views_on_images(std::vector<ImageViews>& views, const std::string& folder) {
  bool named = false;
  for (const ImageViews& sensor : views)
    for (const ImageView& view : sensor.views) named = named || !view.image.empty();
  if (!named) return;
#if KINCAL_WITH_VISION
  const std::string unread = vision::draw_views_on_images(views, folder);
  if (!unread.empty()) note("calibrate", unread + " (--images DIR)");
#else
  (void)folder;
  note("calibrate",
       "the views are drawn without their images: this kincal was built without OpenCV");
#endif
}

}  // namespace

int run_calibrate(const Args& args) {
  po::options_description options("kincal calibrate");
  options.add_options()("model", po::value<std::string>(), "model file (JSON): the nominal values")(
      "data", po::value<std::string>(), "measurement file (CSV)")(
      "out", po::value<std::string>(), "write the calibrated model (JSON, same schema) to FILE")(
      "html", po::value<std::string>(),
      "write the report for people to FILE: one self-contained HTML page with plots")(
      "skip-bad-rows", po::bool_switch(), "drop rows the model cannot reach instead of failing")(
      "folds", po::value<int>(),
      "K-fold cross-validation (K >= 2): configuration i is held out in fold i mod K, the "
      "calibration and the registration-only fit are repeated on the other folds, and the "
      "held-out errors are reported")(
      "rcond",
      po::value<double>()->default_value(IdentifiabilityOptions{}.rcond,
                                         default_text(IdentifiabilityOptions{}.rcond)),
      "numerical rank threshold relative to the largest scaled singular value")(
      "tolerance-priors", po::value<std::string>()->default_value("auto"),
      "priors from the model's stated tolerances (param_error; std = half-width / sqrt(3)) on "
      "the free parameters: auto (with a camera, when no prior is given), on, or off")(
      "step", po::value<std::vector<std::string>>(),
      "calibration in steps: before the full solve, solve for the free parameters matching "
      "these glob patterns only (comma-separated, e.g. 'camera.*'), the others held; repeat "
      "for several steps, in order. The full solve starts where the steps end")(
      "images", po::value<std::string>(),
      "with a camera and --html: the folder the data's `image` column is relative to (default: "
      "the data file's folder); each view is drawn on its image");
  add_json_option(options, "the report");
  add_allow_rank_deficient_option(options);
  add_deprecated_alias(options, "report", "json", po::value<std::string>());
  add_free_fix_options(options);
  add_prior_std_option(options);
  add_noise_std_option(options,
                       "replaces the model's reading_std (weighs the readings against each "
                       "other and a prior, and scales the reported uncertainty)");
  add_solver_options(options);
  add_loss_option(options);
  add_formulation_option(options);
  add_data_size_option(options);
  add_target_option(options);
  add_sensitivity_options(options);
  add_starts_option(options);
  options.add_options()("seed", po::value<Seed>()->default_value(Seed{1}, "1"),
                        "random seed for the starts of --starts");
  add_threads_option(options);
  po::variables_map vm;
  if (!parse_command_line("calibrate", args, options, vm)) return 0;
  const int starts = starts_option(vm);
  const std::optional<TargetAccuracy> target = target_option(vm);
  if (!vm.count("data")) throw CliError("--data FILE is required");
  IdentifiabilityOptions id_options;
  id_options.rcond = vm["rcond"].as<double>();
  if (!(id_options.rcond > 0 && id_options.rcond < 1)) throw CliError("--rcond must be in (0, 1)");

  const int folds = vm.count("folds") ? vm["folds"].as<int>() : 0;
  if (vm.count("folds") && folds < 2)
    throw CliError("--folds must be at least 2 (the number of cross-validation folds)");

  // Every check that does not need the data comes first, so a typo costs nothing.
  reject_loss_as_solver_option(vm);
  SolverChoice choice = make_solver_choice(vm);
  choice.options.num_threads = threads_option(vm);
  apply_loss_option(vm, choice);
  const OutputPlan plan = plan_files(vm);

  CalibrateRequest request;
  request.model_file = vm.count("model") ? vm["model"].as<std::string>() : "";
  request.data_file = vm["data"].as<std::string>();
  std::shared_ptr<MeasurementModel> model = load_model_option(vm);
  apply_free_fix(vm, *model);
  apply_noise_std(vm, *model);
  apply_prior_std(vm, *model);
  check_calibration_model(*model, choice.options.loss, request.model_file);
  const VectorXd nominal = model->parameters().nominal_values();
  const int free_count = model->parameters().num_free();
  request.measurements =
      load_measurements("calibrate", request.data_file, *model, nominal,
                        vm["skip-bad-rows"].as<bool>(), request.model_file, data_limits(vm));
  check_memory(request.data_file, request.measurements.data.size(),
               model->num_readings() * solve_bytes_per_row(free_count), "configuration");
  request.model = model;
  request.solver = std::move(choice.solver);
  request.solver_options = choice.options;
  if (vm.count("formulation")) request.formulation = formulation_choice(vm, *model);
  request.identifiability = id_options;
  request.when_rank_deficient = when_rank_deficient(*model, vm["allow-rank-deficient"].as<bool>(),
                                                    vm.count("free") || vm.count("fix"));
  request.rank_deficiency_remedy = "fix parameters with --fix, or pass --allow-rank-deficient";
  request.folds = folds;
  request.starts = starts;
  request.seed = vm["seed"].as<Seed>().value;
  request.tolerance_priors =
      parse_tolerance_priors(vm["tolerance-priors"].as<std::string>(), "--tolerance-priors");
  if (vm.count("step"))
    for (const std::string& text : vm["step"].as<std::vector<std::string>>())
      request.steps.push_back(parse_calibration_step(text, "--step"));
  request.on_note = [](const std::string& text) { note("calibrate", text); };
  CalibrateResult result = calibrate(request);
  const Summary& summary = result.summary;
  const bool solved = result.solved;

  const std::string report_file = json_output(vm);
  const bool report_to_stdout = (!report_file.empty() && plan.to_stdout("--json")) ||
                                (vm.count("html") && plan.to_stdout("--html"));
  // The free set as solved (identifiability may have fixed some): the others are "fixed".
  const std::optional<SensitivityResult> sensitivity =
      solved ? sensitivity_from_options(vm, model, result.parameters, request.measurements.data,
                                        result.free)
             : std::nullopt;
  // The program's own sections, between the starts and the verdict.
  const std::optional<TargetJudgement> judged =
      target ? std::optional<TargetJudgement>(judge_calibration_target(result, *target))
             : std::nullopt;
  nlohmann::ordered_json extra = nlohmann::ordered_json::object();
  std::string extra_text;
  if (judged) extra["target"] = to_json(*judged);
  if (sensitivity) {
    extra["sensitivity"] = to_json(*sensitivity);
    extra_text += sensitivity_text(*sensitivity);
  }
  if (judged) extra_text += "target: " + judged->verdict + "\n";
  // A camera's views: their reprojection error, and each against the pose its points alone
  // give (models/camera_start.hpp).
  CameraViewChecks views;
  if (solved && has_camera(*model)) {
    views = calibration_camera_views(*model, result.parameters, request.measurements,
                                     request.data_file);
    extra_text += views.text;
    extra["camera_views"] = views.views_json;
    extra["view_checks"] = views.json;
    if (vm.count("html"))
      draw_views_on_images(views.views,
                           vm.count("images")
                               ? vm["images"].as<std::string>()
                               : std::filesystem::path(request.data_file).parent_path().string());
  }
  if (!report_to_stdout) out() << calibration_text(result, extra_text);
  nlohmann::ordered_json report_json = calibration_json(result, extra);
  // Model and report are written together or not at all while the process runs. Under a
  // crash between the two renames the report, renamed first, is new and the model old: the
  // report records the SHA-256 of the model written with it, and `kincal verify` tells.
  std::vector<std::pair<std::string, std::string>> outputs;
  std::string model_text, model_sha256;
  if (solved && vm.count("out")) {
    // It lists what this run estimated as free: a model written after --allow-rank-deficient
    // must not stop again on the parameters that had to be fixed.
    const std::vector<std::string>& fixed = result.fixed_by_identifiability;
    model_text = calibrated_model_text(*model, result.parameters, fixed);
    if (!fixed.empty())
      note("calibrate",
           vm["out"].as<std::string>() + ": lists only the " +
               std::to_string(model->parameters().num_free() - static_cast<int>(fixed.size())) +
               " estimated parameters as free (the " + std::to_string(fixed.size()) +
               " fixed above are fixed there)");
    model_sha256 = sha256_hex(model_text);
    report_json["calibrated_model"] = {{"file", vm["out"].as<std::string>()},
                                       {"sha256", model_sha256}};
  } else {
    report_json["calibrated_model"] = nullptr;
  }
  if (!report_file.empty()) outputs.push_back({"--json", json_report_text(report_json)});
  if (vm.count("html")) {
    report::CalibrationPageExtras page;
    page.target = judged;
    page.sensitivity = sensitivity;
    page.image_views = views.views;
    if (!model_sha256.empty()) {
      page.calibrated_model_file = vm["out"].as<std::string>();
      page.calibrated_model_sha256 = model_sha256;
    }
    outputs.push_back({"--html", report::calibration_html(result, page)});
  }
  if (!model_text.empty()) outputs.push_back({"--out", model_text});
  plan.write(outputs);
  if (!solved) {
    err() << "kincal calibrate: error: the solver did not reach a solution ("
          << to_string(summary.termination) << ": " << summary.message
          << "); no calibrated model written\n";
    return 1;
  }
  if (summary.termination == TerminationType::kMaxIterations)
    note("calibrate", "iteration limit reached before convergence; consider --max-iterations");
  if (!vm.count("out") && !report_to_stdout)
    note("calibrate", "no --out given: the calibrated model was not saved");
  // Written, but not to be loaded: a distinct exit code, so that no script takes it for a
  // plain success.
  if (result.verdict.worst() == Finding::Level::kDoNotLoad) {
    for (const Finding& f : result.verdict.findings)
      if (f.level == Finding::Level::kDoNotLoad) {
        err() << "kincal calibrate: verdict: do not load this calibration: " << f.text << "\n";
        break;
      }
    return kDoNotLoadExitCode;
  }
  return 0;
}

}  // namespace kincal::cli
