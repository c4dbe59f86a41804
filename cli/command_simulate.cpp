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
#include "kincal/cli/model_pair.hpp"
#include "kincal/cli/sha256.hpp"
#include "kincal/cli/shared_options.hpp"
#include "kincal/cli/simulation_report.hpp"
#include "kincal/cli/starts_option.hpp"
#include "kincal/framework/analysis/identifiability_check.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/calibration/measurement_file.hpp"
#include "kincal/framework/design/experiment_design.hpp"
#include "kincal/framework/kinematics/units.hpp"
#include "kincal/models/model_io.hpp"
#include "kincal/models/presets.hpp"

namespace kincal::cli {

namespace {

constexpr const char* kTruthLabel = "--write-data's true model";

void print_errors(const char* label, const PoseErrorStats& e) {
  out() << format_text(
      "  %-8s position mean %10.6f mm  max %10.6f mm   orientation mean %.3e rad  max %.3e rad",
      label, e.position_mean_mm, e.position_max_mm, e.orientation_mean_rad, e.orientation_max_rad);
  if (e.fk_failures) out() << format_text("  (%d poses unreachable)", e.fk_failures);
  out() << format_text("\n");
}

// "5 mm, 0.01 rad" for the units the free parameters (or readings) are in.
std::string per_unit(double mm, double rad, const std::set<std::string>& units) {
  std::string out;
  char buf[64];
  if (units.count(kMillimetre)) {
    std::snprintf(buf, sizeof buf, "±%g mm", mm);
    out += buf;
  }
  if (units.count(kRadian)) {
    std::snprintf(buf, sizeof buf, "%s±%g rad", out.empty() ? "" : ", ", rad);
    out += buf;
  }
  return out;
}

void print_report(const Scenario& scenario, const CalibrationRun& run, int case_id,
                  const std::string& model_name) {
  const ScenarioOptions& o = scenario.options;
  const Summary& s = run.summary;
  const MeasurementModel& model = *scenario.model;
  std::set<std::string> parameter_units, reading_units;
  for (int i : scenario.free_indices) parameter_units.insert(model.parameters()[i].unit);
  for (const auto& u : model.reading_units()) reading_units.insert(u);
  out() << format_text("kincal simulate: %s, ", model_name.c_str());
  if (case_id) out() << format_text("case %d, ", case_id);
  out() << format_text("%d configurations, reading noise %s, %s, seed %llu\n", o.num_configurations,
                       per_unit(o.noise_half_width, o.noise_half_width_rad, reading_units).c_str(),
                       o.truth.size() ? "true model given (--truth)"
                                      : ("parameter errors " +
                                         per_unit(o.param_error_half_width,
                                                  o.param_error_half_width_rad, parameter_units))
                                            .c_str(),
                       static_cast<unsigned long long>(o.seed));
  if (o.prior_std > 0 || o.prior_std_rad > 0) {
    std::string stds;
    char buf[64];
    if (o.prior_std > 0) {
      std::snprintf(buf, sizeof buf, "%g mm", o.prior_std);
      stds += buf;
    }
    if (o.prior_std_rad > 0) {
      std::snprintf(buf, sizeof buf, "%s%g rad", stds.empty() ? "" : ", ", o.prior_std_rad);
      stds += buf;
    }
    out() << format_text(
        "MAP estimate: Gaussian prior of std %s around nominal on every free parameter\n",
        stds.c_str());
  } else {
    int with_prior = 0;
    for (int i : scenario.free_indices) with_prior += model.parameters()[i].has_prior();
    if (with_prior)
      out() << format_text(
          "MAP estimate: Gaussian prior around nominal on %d of %zu free parameters\n", with_prior,
          scenario.free_indices.size());
  }
  out() << format_text("solver %s: %s — %s\n", s.solver.c_str(), to_string(s.termination),
                       s.message.c_str());
  out() << format_text(
      "  %d iterations, %d residual / %d Jacobian evaluations, cost %.6e -> %.6e, "
      "solve %.3f ms\n",
      s.iterations, s.residual_evaluations, s.jacobian_evaluations, s.initial_cost, s.final_cost,
      1e3 * run.solve_seconds);
  out() << format_text("validation over %d poses:\n", o.num_validation);
  print_errors("before", run.before);
  print_errors("after", run.after);
  const FitCheck fit = simulated_fit_check(scenario, run);
  if (fit.too_large())  // only a flagged fit: the JSON holds the check either way
    out() << format_text(
        "fit check: chi-square %.4g on %d degrees of freedom against the simulated "
        "noise, P(larger) %.3g: %s\n",
        fit.chi_square, fit.degrees_of_freedom, fit.p_larger, kFitTooLarge);
  out() << format_text("parameter RMS error after calibration:");
  if (parameter_units.count(kMillimetre)) out() << format_text(" %.6g mm", run.parameter_rms_error);
  if (parameter_units.count(kRadian))
    out() << format_text("%s %.6g rad", parameter_units.count(kMillimetre) ? "," : "",
                         run.parameter_rms_error_rad);
  out() << format_text(" (%zu free parameters)\n", scenario.free_indices.size());
}

// The scenario options with the configurations chosen by experiment design on the nominal
// model (the truth is unknown when a design is made), for the same count, noise and box.
ScenarioOptions designed_options(const po::variables_map& vm, const MeasurementModel& model,
                                 const ScenarioOptions& base, std::string* text) {
  DesignOptions d;
  try {
    d.criterion = parse_design_criterion(vm["design"].as<std::string>());
  } catch (const std::invalid_argument& e) {
    throw CliError(std::string("--design: ") + e.what());
  }
  d.count = base.num_configurations;
  d.num_random = vm["design-candidates"].as<int>();
  if (d.num_random < 0) throw CliError("--design-candidates must be >= 0");
  d.seed = base.seed;
  d.default_error_mm = base.param_error_half_width;
  d.default_error_rad = base.param_error_half_width_rad;
  MeasurementModel designed = model;
  const auto units = model.reading_units();
  d.noise_std = model.reading_std();
  for (int i = 0; i < model.num_readings(); ++i) {
    const double a = base.noise_for(units[i]);
    if (a > 0) d.noise_std[i] = a / std::sqrt(3.0);  // uniform U[-a, a]
  }
  // The prior the calibration will use (ScenarioOptions::prior_std replaces the model's).
  if (base.prior_std > 0 || base.prior_std_rad > 0)
    designed.parameters().for_each_matching("*", [&](Parameter& p) {
      if (p.free) p.prior_std = base.prior_std_for(p.unit);
    });
  for (const Actuator& a : model.mechanism().actuators()) {
    const double r = base.config_range_for(a.unit);
    if (!std::isnan(r)) designed.set_actuator_range(a.name, r);
  }
  check_memory(
      "--design-candidates " + std::to_string(d.num_random), d.num_random,
      kConfigurationBytes + 8.0 * model.num_readings() * (model.parameters().num_free() + 2),
      "candidate");
  const DesignRun run = run_design(designed, d);
  ScenarioOptions out = base;
  out.planned = run.rows;
  out.num_configurations = run.rows.size();
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "configurations chosen by design: criterion %s, %d measurements from %d "
                "candidates, seed %llu",
                to_string(d.criterion), d.count, run.candidates.size(),
                static_cast<unsigned long long>(d.seed));
  *text = buf;
  return out;
}

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
  if (vm.count("noise-std")) {
    if (vm.count("noise-half-width") || vm.count("case"))
      throw CliError(
          "--noise-std is the noise's std, --noise-half-width its half-width, --case sets it: "
          "give one of them");
    const UnitValues std = unit_values_option(vm, "noise-std");
    scenario_options.noise_half_width = std.get(kMillimetre, 0) * std::sqrt(3.0);
    scenario_options.noise_half_width_rad = std.get(kRadian, 0) * std::sqrt(3.0);
  }
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
    scenario_options.prior_std = prior_std.get(kMillimetre, 0);
    scenario_options.prior_std_rad = prior_std.get(kRadian, 0);
  }
  SolverChoice choice = make_solver_choice(vm);
  choice.options.num_threads = threads_option(vm);
  const int starts = starts_option(vm);

  // Every file is checked before the run, so a typo does not cost a solve.
  OutputPlan plan;
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
  if (prior_per_unit)
    for (int i : model->parameters().free_indices()) {
      const Parameter& p = model->parameters()[i];
      if (!prior_std.has(p.unit))
        throw CliError("--prior-std gives no std in " + p.unit + " for free parameter " + p.name +
                       "; expected one per unit of the free parameters, e.g. 2.887mm,0.0058rad, "
                       "or per pattern, e.g. '*.z=0.5mm'");
    }
  if (!prior_rules.empty() && !prior_per_unit) apply_prior_std(vm, *model);
  if (vm.count("truth")) {
    const std::string path = vm["truth"].as<std::string>();
    const std::shared_ptr<MeasurementModel> truth = load_model_file(path);
    check_same_parameters(*truth, "--truth " + printable(path), *model,
                          vm.count("model") ? "--model " + printable(model_name)
                                            : "the preset " + printable(model_name));
    scenario_options.truth = truth->parameters().nominal_values();
  }
  if (vm.count("configs")) {
    // The actuator columns; the readings only say which are taken (a design template has
    // none). Reachability is checked where the readings are simulated, with the truth.
    const std::string path = vm["configs"].as<std::string>();
    MeasurementTable table;
    try {
      table = read_model_columns(path, *model, data_limits(vm));
    } catch (const std::invalid_argument& e) {
      throw measurement_file_error(e);
    }
    Measurements rows = table.data;
    // A row without readings (a template) takes every reading; otherwise the readings given.
    for (int r = 0; r < rows.size(); ++r)
      if (rows.readings.row(r).array().isNaN().all()) rows.readings.row(r).setZero();
    scenario_options.planned = rows;
    scenario_options.num_configurations = rows.size();
  }
  const int free_parameters = model->parameters().num_free();
  check_memory("--poses " + std::to_string(scenario_options.num_configurations),
               scenario_options.num_configurations,
               kConfigurationBytes + model->num_readings() * solve_bytes_per_row(free_parameters),
               "configuration");
  check_memory("--validation " + std::to_string(scenario_options.num_validation),
               scenario_options.num_validation, kConfigurationBytes, "pose");
  ScenarioOptions run_options = scenario_options;
  std::string design_text;
  if (vm.count("design"))
    run_options = designed_options(vm, *model, scenario_options, &design_text);
  Scenario scenario;
  try {
    scenario = make_scenario(model, run_options);
  } catch (const std::invalid_argument& e) {
    if (!vm.count("prior-std")) throw;
    throw CliError(std::string("--prior-std: ") + e.what());
  } catch (const std::runtime_error& e) {
    if (!vm.count("configs")) throw;
    throw CliError("--configs " + printable(vm["configs"].as<std::string>()) + ": " + e.what());
  }
  // As in calibrate: fewer readings than unknowns cannot determine them (the paper needs
  // m > n), and a solver would report a perfect fit of a wrong geometry.
  const long long readings =
      static_cast<long long>(scenario.calibration.size()) * scenario.model->num_readings();
  const int unknowns = static_cast<int>(scenario.free_indices.size());
  if (readings < unknowns)
    throw CliError((vm.count("configs")
                        ? "--configs " + printable(vm["configs"].as<std::string>()) + " (" +
                              std::to_string(scenario.calibration.size()) + " configurations)"
                        : "--poses " + std::to_string(scenario.calibration.size())) +
                   ": " + std::to_string(readings) + " readings cannot determine " +
                   std::to_string(unknowns) + " free parameters (need at least " +
                   std::to_string((unknowns + scenario.model->num_readings() - 1) /
                                  scenario.model->num_readings()) +
                   " configurations; see kincal observability)");
  // The same identifiability check as calibrate's, on the simulated data at the nominal
  // values: calibrate refuses data that cannot determine the free parameters, and a solve of
  // them would end "converged" somewhere in a valley of equally good fits.
  std::vector<std::string> fixed_by_identifiability;
  {
    const std::shared_ptr<CalibrationProblem> problem = scenario.make_problem();
    VectorXd r;
    MatrixXd J;
    if (problem->evaluate(problem->initial_free_parameters(), &r, &J)) {
      const IdentifiabilityCheck check = check_identifiability(
          "the simulated data (" + std::to_string(scenario.calibration.size()) +
              " configurations, seed " + std::to_string(scenario.options.seed) + ")",
          *problem, J, when_rank_deficient(*model, vm["allow-rank-deficient"].as<bool>(), false),
          IdentifiabilityOptions{},
          "widen --config-range, measure more --poses, fix parameters (the model file's "
          "\"free\" list), or pass --allow-rank-deficient");
      for (const std::string& text : check.notes) note("simulate", text);
      scenario.free_indices = check.free;
      fixed_by_identifiability = check.fixed;
    }
  }
  // Several starts: the best is solved again with the per-iteration validation errors.
  const Formulation formulation = formulation_choice(vm, *scenario.model);
  StartsReport starts_report;
  CalibrationRun run;
  if (starts > 1) {
    if (formulation == Formulation::kImplicit)
      note("simulate",
           "--starts solves the nested formulation; the best start is solved again "
           "in the implicit one");
    starts_report.result = solve_scenario_starts(scenario, *choice.solver, choice.options, starts,
                                                 choice.options.num_threads);
    starts_report.seed = scenario.options.seed;
    starts_report.spread_from = "the simulated parameter errors";
    const MultiStartResult& result = starts_report.result;
    const StartOutcome& best = result.starts[result.best_start];
    if (result.stopped) {
      // Stopped (the Python bindings' Ctrl-C): the estimate is where the best start got to.
      // Its solve from there stops at once, the stop being still asked for; the summary is
      // the starts' own.
      run = run_calibration(scenario, *choice.solver, choice.options, true, formulation, best.x);
      run.summary = result.estimate_summary();
    } else {
      run =
          run_calibration(scenario, *choice.solver, choice.options, true, formulation, best.start);
    }
  } else {
    run = run_calibration(scenario, *choice.solver, choice.options, true, formulation);
    const auto problem = scenario.make_problem();
    VectorXd x(scenario.free_indices.size());
    for (int i = 0; i < x.size(); ++i) x[i] = run.estimate[scenario.free_indices[i]];
    starts_report = single_start_report(problem->initial_free_parameters(), x, run.summary,
                                        scenario.options.seed);
  }
  if (!run.formulation_note.empty()) note("simulate", run.formulation_note);

  const bool json_to_stdout = vm.count("json") && plan.to_stdout("--json");
  if (!json_to_stdout) {
    if (!design_text.empty()) out() << format_text("%s\n", design_text.c_str());
    print_report(scenario, run, case_id, model_name);
    out() << starts_text(starts_report);
  }
  // All outputs or none while the process runs (data without its truth file is useless);
  // the data file names its truth file's SHA-256, for a check after a crash.
  std::vector<std::pair<std::string, std::string>> outputs;
  if (vm.count("json")) {
    auto json = to_json(scenario, run, case_id, model_name);
    json["format"] = "kincal-simulate";  // keys are sorted in this document
    json["version"] = 1;
    json["design"] = vm.count("design") ? nlohmann::json(design_text) : nlohmann::json();
    json["fixed_by_identifiability"] = fixed_by_identifiability;
    const FitCheck fit = simulated_fit_check(scenario, run);
    json["fit_check"] = {
        {"verdict", !fit.tested       ? "not_tested"
                    : fit.too_large() ? "too_large"
                                      : "consistent"},
        {"chi_square", fit.tested ? nlohmann::json(fit.chi_square) : nlohmann::json()},
        {"degrees_of_freedom",
         fit.tested ? nlohmann::json(fit.degrees_of_freedom) : nlohmann::json()},
        {"p_larger", fit.tested ? nlohmann::json(fit.p_larger) : nlohmann::json()},
        {"note", fit.tested ? (fit.too_large() ? kFitTooLarge : kFitConsistent) : fit.not_tested}};
    json["starts"] = starts_json(starts_report);
    // Where the configurations and the truth came from (null: drawn from the seed).
    json["configs"] =
        vm.count("configs") ? nlohmann::json(vm["configs"].as<std::string>()) : nlohmann::json();
    json["truth_model"] =
        vm.count("truth") ? nlohmann::json(vm["truth"].as<std::string>()) : nlohmann::json();
    outputs.push_back({"--json", json.dump(2) + "\n"});
  }
  if (vm.count("trace")) outputs.push_back({"--trace", trace_csv(run)});
  if (vm.count("write-data")) {
    const std::string truth = model_to_json(*model, scenario.truth).dump(2) + "\n";
    char noise[96];
    std::snprintf(noise, sizeof noise, "%g mm, %g rad", scenario_options.noise_half_width,
                  scenario_options.noise_half_width_rad);
    const std::string comment =
        "kincal simulate: " + printable(model_name) + ", " +
        std::to_string(scenario_options.num_configurations) + " configurations" +
        (vm.count("configs") ? " of " + printable(vm["configs"].as<std::string>())
                             : std::string()) +
        ", reading noise U[-a, a] with a = " + noise + ", seed " +
        std::to_string(scenario_options.seed) +
        (vm.count("truth")
             ? ", true model given by --truth " + printable(vm["truth"].as<std::string>())
             : std::string()) +
        "\ntrue model: " + printable(truth_file) + " (sha256 " + sha256_hex(truth) + ")";
    outputs.push_back({kTruthLabel, truth});
    outputs.push_back({"--write-data", measurements_to_csv(scenario.calibration,
                                                           model->mechanism().actuator_names(),
                                                           model->reading_names(), comment)});
  }
  plan.write(outputs);
  // As calibrate: a solve that reached no solution is exit code 1, outputs written.
  if (!run.summary.converged() && run.summary.termination != TerminationType::kMaxIterations) {
    err() << "kincal simulate: error: the solver did not reach a solution ("
          << to_string(run.summary.termination) << ": " << run.summary.message << ")\n";
    return 1;
  }
  return 0;
}

}  // namespace kincal::cli
