// kincal simulate: one simulated calibration of any registered model or model file, readable
// or as JSON.

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <set>

#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/memory_check.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/cli/project_record.hpp"
#include "kincal/cli/shared_options.hpp"
#include "kincal/cli/simulation_report.hpp"
#include "kincal/cli/starts_option.hpp"
#include "kincal/framework/analysis/identifiability_check.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/calibration/measurement_file.hpp"
#include "kincal/framework/design/experiment_design.hpp"
#include "kincal/framework/io/sha256.hpp"
#include "kincal/framework/kinematics/model_pair.hpp"
#include "kincal/framework/kinematics/units.hpp"
#include "kincal/models/model_io.hpp"
#include "kincal/models/presets.hpp"

namespace kincal::cli {

namespace {

constexpr const char* kTruthLabel = "--write-data's true model";

}  // namespace

int run_simulate(const Args& args) {
  po::options_description options("kincal simulate");
  add_scenario_options(options, true);
  add_data_size_option(options);
  add_solver_options(options);
  add_threads_option(options);
  add_formulation_option(options);
  add_json_option(options, "the result");
  options.add_options()("trace", po::value<std::string>(),
                        "write the per-iteration trace as CSV to FILE")(
      "design", po::value<std::string>(),
      "choose the configurations by experiment design with this criterion (D, A, E or I; "
      "kincal design) instead of drawing them at random")(
      "design-candidates", po::value<int>()->default_value(10000),
      "random candidate configurations for --design (the box's corners are added)");
  // A prior makes the calibration a MAP estimate; the readings are weighed by the noise's
  // std a / sqrt(3) unless the model states reading_std.
  add_prior_std_option(options);
  // Files for the calibrate workflow (docs/calibrating-a-machine.md).
  options.add_options()("preset", po::value<std::string>(),
                        "built-in model to simulate (kincal list models; default cube-hexapod)")(
      "model", po::value<std::string>(),
      "model file (JSON) to simulate instead of a preset; its free parameters get the errors")(
      "write-data", po::value<std::string>(),
      "write the simulated measurements as CSV to FILE, and the true model beside it as "
      "<FILE stem>.truth.json")(
      "configs", po::value<std::string>(),
      "simulate the configurations of this measurement file (e.g. a design template: its "
      "actuator columns; readings given mark the ones taken, a row without any takes all) "
      "instead of drawing --poses at random")(
      "truth", po::value<std::string>(),
      "the true model (a model file with the same parameters as --model, e.g. a "
      "<stem>.truth.json) instead of drawing --param-error errors");
  add_allow_rank_deficient_option(options);
  add_starts_option(options);
  add_noise_std_option(options,
                       "each simulated reading gets uniform noise of this std (U[-a, a] with a "
                       "= std x sqrt(3)); instead of --noise-half-width");
  po::variables_map vm;
  if (!parse_command_line("simulate", args, options, vm)) return 0;

  int case_id = 0;
  ScenarioOptions scenario_options = scenario_options_from(vm, &case_id);
  if (vm.count("configs") && (vm.count("poses") || vm.count("case") || vm.count("design")))
    throw CliError(
        "--configs gives the configurations: give it without --poses, --case and "
        "--design");
  if (vm.count("truth") && !vm["param-error"].defaulted())
    throw CliError("--truth gives the true model: give it without --param-error");
  // Priors per unit only are the scenario's (every free parameter of a unit, in the JSON as
  // prior_std_mm and prior_std_rad); with a pattern they are set on the model itself below.
  const std::vector<PriorStdRule> prior_rules = prior_std_rules(vm);
  const bool prior_per_unit = !prior_rules.empty() && prior_std_per_unit_only(prior_rules);
  UnitValues prior_std;
  if (prior_per_unit) {
    for (const PriorStdRule& rule : prior_rules) prior_std.set(rule.unit, rule.value);
    scenario_options.prior_std = prior_std;
  }
  SolverChoice choice = make_solver_choice(vm);
  choice.options.num_threads = threads_option(vm);
  const int starts = starts_option(vm);

  // Every file is checked before the run, so a typo does not cost a solve.
  OutputPlan plan(console_output());
  for (const char* option : {"model", "configs", "truth"})
    if (vm.count(option)) plan.input(std::string("--") + option, vm[option].as<std::string>());
  for (const char* option : {"json", "trace"})
    if (vm.count(option)) plan.output(std::string("--") + option, vm[option].as<std::string>());
  std::string truth_file;
  if (vm.count("write-data")) {
    const std::string data_file = vm["write-data"].as<std::string>();
    if (data_file == "-") throw CliError("--write-data needs a file name (it writes two files)");
    truth_file = std::filesystem::path(data_file).replace_extension(".truth.json").string();
    plan.output("--write-data", data_file);
    plan.output(kTruthLabel, truth_file);
  }
  plan.check();
  if (vm.count("preset") && vm.count("model"))
    throw CliError("give either --preset NAME or --model FILE, not both");
  std::string model_name = "cube-hexapod";
  std::shared_ptr<MeasurementModel> model;
  if (vm.count("model")) {
    model_name = vm["model"].as<std::string>();
    model = load_model_option(vm);
  } else {
    if (vm.count("preset")) model_name = vm["preset"].as<std::string>();
    try {
      model = make_preset(model_name);
    } catch (const std::invalid_argument& e) {
      throw CliError(std::string("--preset: ") + e.what());
    }
  }
  if (!prior_rules.empty() && !prior_per_unit) apply_prior_std(vm, *model);
  SimulateRequest request;
  if (vm.count("truth")) {
    const std::string path = vm["truth"].as<std::string>();
    const std::shared_ptr<MeasurementModel> truth = load_model_file(path);
    check_same_parameters(*truth, "--truth " + printable(path), *model,
                          vm.count("model") ? "--model " + printable(model_name)
                                            : "the preset " + printable(model_name));
    scenario_options.truth = truth->parameters().nominal_values();
    request.truth_file = path;
  }
  if (vm.count("configs")) {
    // The actuator columns; the readings only say which are taken (a design template has
    // none). Reachability is checked where the readings are simulated, with the truth.
    request.configs_file = vm["configs"].as<std::string>();
    MeasurementTable table;
    try {
      table = read_model_columns(request.configs_file, *model, data_limits(vm));
    } catch (const std::invalid_argument& e) {
      throw measurement_file_error(e);
    }
    scenario_options.planned = planned_rows(table.data);
    scenario_options.num_configurations = table.data.size();
  }
  const int free_parameters = model->parameters().num_free();
  check_memory("--poses " + std::to_string(scenario_options.num_configurations),
               scenario_options.num_configurations,
               kConfigurationBytes + model->num_readings() * solve_bytes_per_row(free_parameters),
               "configuration");
  check_memory("--validation " + std::to_string(scenario_options.num_validation),
               scenario_options.num_validation, kConfigurationBytes, "pose");
  if (vm.count("design")) {
    try {
      request.design = parse_design_criterion(vm["design"].as<std::string>());
    } catch (const std::invalid_argument& e) {
      throw CliError(std::string("--design: ") + e.what());
    }
    request.design_candidates = vm["design-candidates"].as<int>();
    if (request.design_candidates < 0) throw CliError("--design-candidates must be >= 0");
    check_memory(
        "--design-candidates " + std::to_string(request.design_candidates),
        request.design_candidates,
        kConfigurationBytes + 8.0 * model->num_readings() * (model->parameters().num_free() + 2),
        "candidate");
  }
  request.model = model;
  request.scenario = scenario_options;
  request.solver = std::move(choice.solver);
  request.solver_options = choice.options;
  if (vm.count("formulation")) request.formulation = formulation_choice(vm, *model);
  request.starts = starts;
  request.allow_rank_deficient = vm["allow-rank-deficient"].as<bool>();
  request.model_name = model_name;
  request.case_id = case_id;
  request.priors_given = vm.count("prior-std") > 0;
  request.rank_deficiency_remedy =
      "widen --config-range, measure more --poses, fix parameters (the model file's "
      "\"free\" list), or pass --allow-rank-deficient";
  request.on_note = [](const std::string& text) { note("simulate", text); };
  const SimulateResult result = simulate(request);

  const bool json_to_stdout = vm.count("json") && plan.to_stdout("--json");
  if (!json_to_stdout) out() << simulation_text(result);
  // All outputs or none while the process runs (data without its truth file is useless);
  // the data file names its truth file's SHA-256, for a check after a crash.
  std::vector<std::pair<std::string, std::string>> outputs;
  if (vm.count("json")) outputs.push_back({"--json", json_report_text(simulation_json(result))});
  if (vm.count("trace")) outputs.push_back({"--trace", simulation_trace_csv(result.run)});
  if (vm.count("write-data")) {
    const std::string truth = model_to_json(*model, result.scenario.truth).dump(2) + "\n";
    outputs.push_back({kTruthLabel, truth});
    outputs.push_back({"--write-data", simulated_data_csv(result, truth_file, truth)});
  }
  plan.write(outputs);
  // As calibrate: a solve that reached no solution is exit code 1, outputs written.
  if (!result.solved) {
    err() << "kincal simulate: error: the solver did not reach a solution ("
          << to_string(result.run.summary.termination) << ": " << result.run.summary.message
          << ")\n";
    return 1;
  }
  return 0;
}

}  // namespace kincal::cli
