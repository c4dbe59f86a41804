// kincal design: chooses the configurations (and, for a model with several sensors, the
// sensor placements) to measure, and writes them as a measurement template that calibrate
// reads once the readings are filled in.

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <set>
#include <sstream>

#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/design_progress.hpp"
#include "kincal/cli/interrupt.hpp"
#include "kincal/cli/memory_check.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/cli/project_record.hpp"
#include "kincal/cli/shared_options.hpp"
#include "kincal/cli/simulation_report.hpp"
#include "kincal/cli/target_accuracy.hpp"
#include "kincal/framework/analysis/identifiability_check.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/calibration/measurement_file.hpp"
#include "kincal/framework/design/experiment_design.hpp"
#include "kincal/framework/kinematics/units.hpp"
#include "kincal/framework/report/pages.hpp"
#include "kincal/framework/workflows/design.hpp"

namespace kincal::cli {

namespace {

using Json = nlohmann::ordered_json;

// n x n matrices design holds at once, at most: the prior and existing data, the workspace
// weight, the exchange's M, M^-1, M0 and W, a criterion's eigenvectors and inverse, the
// covariances compared, and temporaries.
constexpr double kDesignMatrices = 16;

void apply_config_range(const po::variables_map& vm, MeasurementModel& model) {
  if (!vm.count("config-range")) return;
  const UnitValues range = unit_values_option(vm, "config-range");
  for (const Actuator& a : model.mechanism().actuators())
    if (range.has(a.unit)) model.set_actuator_range(a.name, range.get(a.unit));
}

}  // namespace

int run_design(const Args& args) {
  po::options_description options("kincal design");
  options.add_options()("model", po::value<std::string>(), "model file (JSON)")(
      "poses", po::value<int>(), "number of configurations to choose")(
      "criterion", po::value<std::string>()->default_value("D"),
      "D (parameters' confidence volume), A (mean parameter variance), E (worst direction) or I "
      "(mean predicted position variance over the workspace)")(
      "candidates", po::value<int>()->default_value(10000),
      "random candidate configurations drawn in the box (the box's corners are added)")(
      "existing", po::value<std::string>(),
      "measurement file (CSV) already measured: its readings count as information, and the "
      "design adds to them")(
      "within", po::value<std::string>(),
      "draw the candidates in the range of the configurations of this CSV file (each "
      "actuator from its least to its largest value: where the robot was measured), instead "
      "of the box around home")(
      "centre", po::value<std::string>(),
      "q1,q2,...: draw the candidates around this configuration (in the actuators' units) "
      "instead of home, ± --config-range (default each actuator's range), within the joint "
      "limits")(
      "candidates-file", po::value<std::string>(),
      "take the candidate configurations from this CSV file (the model's actuator columns, "
      "unit suffixes allowed) instead of drawing them")(
      "singularity-margin",
      po::value<double>()->default_value(DesignOptions{}.min_singularity_margin),
      "keep configurations whose conditioning is at least this fraction of home's")(
      "orientation-length", po::value<std::string>(),
      "criterion I only: also weigh the orientation error, a rotation of 1 rad counting as a "
      "displacement of this length, e.g. 300mm (the tool's reach; default: position only)")(
      "bound", po::bool_switch(),
      "also bound how good any design of --poses measurements from these candidates can be "
      "(D, A, I: the continuous relaxation's optimum, certified; a fraction of a second for "
      "10^4 hexapod candidates, 2 s for 10^5), and say how close the design comes to it")(
      "seed", po::value<Seed>()->default_value(Seed{1}, "1"),
      "random seed (candidates, workspace samples, the random design compared with)")(
      "out", po::value<std::string>(), "write the measurement template (CSV) to FILE")(
      "html", po::value<std::string>(),
      "write the design for people to FILE: one self-contained HTML page");
  add_json_option(options, "the design");
  add_config_range_option(options);
  add_noise_std_option(options,
                       "weighs the readings in the design and scales its predictions (default: "
                       "the model's reading_std; one of them is required)");
  add_deprecated_alias(options, "count", "poses", po::value<int>());
  add_free_fix_options(options);
  add_prior_std_option(options);
  add_data_size_option(options);
  add_progress_option(options);
  add_target_option(options);
  po::variables_map vm;
  if (!parse_command_line("design", args, options, vm)) return 0;
  const std::optional<TargetAccuracy> target = target_option(vm);
  if (!vm.count("poses")) throw CliError("--poses N is required (the configurations to choose)");
  if (!vm.count("out")) throw CliError("--out FILE is required (the measurement template)");
  DesignOptions design;
  design.count = vm["poses"].as<int>();
  design.num_random = vm["candidates"].as<int>();
  design.seed = vm["seed"].as<Seed>().value;
  design.min_singularity_margin = vm["singularity-margin"].as<double>();
  try {
    design.criterion = parse_design_criterion(vm["criterion"].as<std::string>());
  } catch (const std::invalid_argument& e) {
    throw CliError(std::string("--criterion: ") + e.what());
  }
  if (design.count < 1) throw CliError("--poses must be at least 1");
  if (design.num_random < 0) throw CliError("--candidates must be >= 0");
  if (!(design.min_singularity_margin >= 0)) throw CliError("--singularity-margin must be >= 0");
  if (vm.count("orientation-length")) {
    if (design.criterion != DesignCriterion::kI)
      throw CliError("--orientation-length applies to --criterion I only");
    const UnitValues length = unit_values_option(vm, "orientation-length");
    if (length.values().size() != 1 || !length.has(kMillimetre))
      throw CliError("--orientation-length '" + vm["orientation-length"].as<std::string>() +
                     "': expected a length, e.g. 300mm");
    design.orientation_length = length.get(kMillimetre);
    if (!(design.orientation_length >= 0) || !std::isfinite(design.orientation_length))
      throw CliError("--orientation-length '" + vm["orientation-length"].as<std::string>() +
                     "': expected a finite length >= 0");
  }
  OutputPlan plan(console_output());
  for (const char* option : {"model", "existing", "within", "candidates-file"})
    if (vm.count(option)) plan.input(std::string("--") + option, vm[option].as<std::string>());
  plan.output("--out", vm["out"].as<std::string>());
  if (plan.to_stdout("--out")) throw CliError("--out needs a file name (the template)");
  if (vm.count("json")) plan.output("--json", vm["json"].as<std::string>());
  if (vm.count("html")) plan.output("--html", vm["html"].as<std::string>());
  plan.check();

  ExperimentDesignRequest request;
  request.model_file = vm.count("model") ? vm["model"].as<std::string>() : "";
  const std::string& model_file = request.model_file;
  std::shared_ptr<MeasurementModel> model = load_model_option(vm);
  apply_free_fix(vm, *model);
  apply_prior_std(vm, *model);
  apply_config_range(vm, *model);
  const int n = model->parameters().num_free();
  if (n == 0) throw CliError("no free parameters: nothing to design for (use --free)");
  if (!vm.count("noise-std") && !model->weighted())
    throw CliError((model_file.empty() ? std::string("the model") : printable(model_file)) +
                   " states no reading_std: give the readings' noise std, e.g. --noise-std "
                   "0.0072mm (or reading_std in the model file)");
  if (vm.count("noise-std")) {
    request.noise_std = noise_std_per_reading(vm, *model);
    request.noise_source = "--noise-std";
  }
  // The n x n matrices first (a model of 10^4 free parameters needs GBs of them), then the
  // candidates' rows beside them: the exchange keeps each row, its transpose and M^-1 times
  // it (and W M^-1 times it for A and I), and the workspace samples hold 6 rows each.
  const double matrix_bytes =
      kDesignMatrices * 8.0 * n * n + 8.0 * 6 * n * DesignOptions{}.workspace_samples;
  check_memory_square((model_file.empty() ? std::string("the model") : model_file) + " (" +
                          std::to_string(n) + " free parameters)",
                      n, kDesignMatrices, "free parameter",
                      8.0 * 6 * n * DesignOptions{}.workspace_samples);
  check_memory("--candidates " + std::to_string(design.num_random), design.num_random,
               kConfigurationBytes + 8.0 * model->num_readings() * (4.0 * n + 2 * 16 + 2),
               "candidate", matrix_bytes);
  if (vm.count("within") + vm.count("candidates-file") + vm.count("centre") > 1)
    throw CliError("give one of --within, --candidates-file and --centre");
  if (vm.count("centre")) {
    const int na = model->mechanism().num_actuators();
    const auto v = parse_numbers(vm["centre"].as<std::string>(), na, "centre",
                                 "one value per actuator, in its unit");
    design.centre = Eigen::Map<const VectorXd>(v.data(), na);
  }
  for (const char* option : {"within", "candidates-file"}) {
    if (!vm.count(option)) continue;
    const std::string path = vm[option].as<std::string>();
    MatrixXd q;
    try {
      q = read_configurations(path, *model, data_limits(vm));
    } catch (const std::invalid_argument& e) {
      throw CliError(std::string("--") + option + ": " + e.what());
    }
    if (std::string(option) == "within") {
      design.box_low = q.colwise().minCoeff().transpose();
      design.box_high = q.colwise().maxCoeff().transpose();
    } else {
      design.given = q;
    }
  }
  if (vm.count("existing")) {
    const LoadedData loaded =
        load_measurements("design", vm["existing"].as<std::string>(), *model,
                          model->parameters().nominal_values(), false, model_file, data_limits(vm));
    note_copied_rows("design", loaded);
    request.existing = loaded.data;
  }
  // Progress per stage on stderr, and Ctrl-C: the first one stops the work with the best
  // design so far (marked partial, exit 130), the second one aborts.
  DesignProgress progress(progress_wanted(vm));
  const InterruptGuard interrupt_guard("design");
  design.monitor = progress.monitor();
  request.model = model;
  request.options = design;
  request.bound = vm["bound"].as<bool>();
  // As calibrate: an arm imported from a URDF, its mask untouched, is designed for what the
  // candidates determine.
  request.when_rank_deficient =
      when_rank_deficient(*model, false, vm.count("free") || vm.count("fix"));
  request.on_note = [](const std::string& text) { note("design", text); };
  const ExperimentDesignResult result = design_experiment(request);
  progress.finish();
  if (result.stopped_before_design) {
    err() << format_text(
        "kincal design: interrupted while drawing candidates: %d reachable so far, "
        "fewer than --poses %d; nothing written\n",
        result.candidates.size(), design.count);
    return 130;  // the shell's code for a run ended by SIGINT
  }
  const std::string template_path = vm["out"].as<std::string>();
  const std::optional<TargetJudgement> judged =
      target ? std::optional<TargetJudgement>(judge_predicted_target(*target, result.designed_pose))
             : std::nullopt;
  const bool json_to_stdout = (vm.count("json") && plan.to_stdout("--json")) ||
                              (vm.count("html") && plan.to_stdout("--html"));
  if (!json_to_stdout) {
    out() << design_text(result, template_path);
    if (judged) out() << format_text("target: %s\n", judged->verdict.c_str());
  }
  std::vector<std::pair<std::string, std::string>> outputs;
  if (vm.count("json") || vm.count("html")) {
    const Json j = design_json(result, template_path, judged ? to_json(*judged) : Json());
    if (vm.count("json")) outputs.push_back({"--json", json_report_text(j)});
    if (vm.count("html"))
      outputs.push_back({"--html", report::design_html(result, template_path, judged)});
  }
  outputs.push_back({"--out", design_template_csv(result)});
  plan.write(outputs);
  if (result.partial) {
    err() << format_text(
        "kincal design: interrupted in the %s: wrote the best design found so far, "
        "marked partial (a full run may do better)\n",
        result.stopped_in.c_str());
    return 130;  // the shell's code for a run ended by SIGINT
  }
  return 0;
}

}  // namespace kincal::cli
