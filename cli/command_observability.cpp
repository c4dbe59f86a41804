// kincal observability: identifiability of a model's free parameters from a measurement
// file or from simulated configurations, before any solving.

#include <cmath>
#include <cstdio>
#include <iostream>

#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/html_pages.hpp"
#include "kincal/cli/memory_check.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/cli/sensitivity_option.hpp"
#include "kincal/cli/shared_options.hpp"
#include "kincal/cli/simulation_report.hpp"
#include "kincal/framework/analysis/calibration_report.hpp"
#include "kincal/framework/analysis/fixed_parameter_sensitivity.hpp"
#include "kincal/framework/analysis/identifiability_words.hpp"
#include "kincal/framework/calibration/constrained_problem.hpp"
#include "kincal/framework/calibration/frame_turns.hpp"
#include "kincal/framework/calibration/prior_problem.hpp"
#include "kincal/framework/calibration/simulation.hpp"

namespace kincal::cli {

int run_observability(const Args& args) {
  po::options_description options("kincal observability");
  options.add_options()("model", po::value<std::string>(), "model file (JSON)")(
      "data", po::value<std::string>(), "measurement file (CSV) whose configurations to analyse")(
      "poses", po::value<int>(),
      "instead of --data: this many random configurations, home actuator values + U[-r, r]")(
      "seed", po::value<Seed>()->default_value(Seed{1}, "1"), "random seed for --poses")(
      "rcond",
      po::value<double>()->default_value(IdentifiabilityOptions{}.rcond,
                                         default_text(IdentifiabilityOptions{}.rcond)),
      "numerical rank threshold relative to the largest scaled singular value")(
      "skip-bad-rows", po::bool_switch(), "drop rows the model cannot reach instead of failing");
  add_sensitivity_options(options);
  options.add_options()("html", po::value<std::string>(),
                        "write the analysis for people to FILE: one self-contained HTML page");
  add_json_option(options, "the analysis");
  add_config_range_option(options);
  add_free_fix_options(options);
  add_prior_std_option(options);
  add_noise_std_option(options,
                       "replaces the model's reading_std (weighs the readings, scales "
                       "the predicted standard deviations)");
  add_data_size_option(options);
  po::variables_map vm;
  if (!parse_command_line("observability", args, options, vm)) return 0;
  if (vm.count("data") == vm.count("poses"))
    throw CliError("give exactly one of --data FILE and --poses M");
  IdentifiabilityOptions id_options;
  id_options.rcond = vm["rcond"].as<double>();
  if (!(id_options.rcond > 0 && id_options.rcond < 1)) throw CliError("--rcond must be in (0, 1)");
  OutputPlan plan;
  for (const char* option : {"model", "data"})
    if (vm.count(option)) plan.input(std::string("--") + option, vm[option].as<std::string>());
  if (vm.count("json")) plan.output("--json", vm["json"].as<std::string>());
  if (vm.count("html")) plan.output("--html", vm["html"].as<std::string>());
  plan.check();

  std::shared_ptr<MeasurementModel> model = load_model_option(vm);
  apply_free_fix(vm, *model);
  apply_noise_std(vm, *model);
  apply_prior_std(vm, *model);
  const bool with_prior =
      check_prior_usable(*model, vm.count("model") ? vm["model"].as<std::string>() : "the model");
  const VectorXd values = model->parameters().nominal_values();
  const std::vector<int> free = model->parameters().free_indices();
  if (free.empty()) throw CliError("no free parameters: nothing to analyse (use --free)");

  Measurements data;
  if (vm.count("data")) {
    const LoadedData loaded = load_measurements("observability", vm["data"].as<std::string>(),
                                                *model, values, vm["skip-bad-rows"].as<bool>(),
                                                vm["model"].as<std::string>(), data_limits(vm));
    note_copied_rows("observability", loaded);
    data = loaded.data;
    check_memory(vm["data"].as<std::string>(), data.size(),
                 model->num_readings() * solve_bytes_per_row(static_cast<int>(free.size())),
                 "configuration");
  } else {
    ScenarioOptions s;
    s.num_configurations = vm["poses"].as<int>();
    s.seed = vm["seed"].as<Seed>().value;
    if (vm.count("config-range")) {
      const UnitValues range = unit_values_option(vm, "config-range");
      s.config_range = range.get(kMillimetre, s.config_range);
      s.config_range_rad = range.get(kRadian, s.config_range_rad);
    }
    // Configurations the model's own values reach: no parameter errors, not even the
    // per-parameter ones of the model file.
    s.param_error_half_width = s.param_error_half_width_rad = 0;
    s.num_validation = 0;
    if (s.num_configurations < 1) throw CliError("--poses must be at least 1");
    check_memory("--poses " + std::to_string(s.num_configurations), s.num_configurations,
                 kConfigurationBytes +
                     model->num_readings() * solve_bytes_per_row(static_cast<int>(free.size())),
                 "configuration");
    auto exact = std::make_shared<MeasurementModel>(*model);
    exact->parameters().for_each_matching("*", [](Parameter& p) { p.error_half_width = 0; });
    data = make_scenario(exact, s).calibration;
  }

  const CalibrationProblem problem(model, data, values, free);
  VectorXd residuals;
  MatrixXd J;
  std::string why;
  if (!problem.evaluate(problem.initial_free_parameters(), &residuals, &J, &why))
    throw CliError("cannot evaluate the identification Jacobian: " + why);
  // Only the readings present count, as in calibrate's report: a missing one is a zero row
  // that would count as a residual (and lower O1) without having been observed.
  const std::vector<int> present = problem.data().present_rows();
  J = J(present, Eigen::all).eval();
  residuals = residuals(present).eval();
  // Turns of the measurement frame that change no fit (sockets measured as 0), as calibrate
  // counts them: a gauge freedom the Jacobian does not show.
  MatrixXd turns = measurement_frame_turns(problem, problem.initial_free_parameters());
  if (turns.cols()) {
    std::vector<int> rows = present;
    for (Eigen::Index i = problem.data().readings.size(); i < turns.rows(); ++i)
      rows.push_back(static_cast<int>(i));
    turns = turns(rows, Eigen::all).eval();
  }
  // The model's parameter-only constraints (a known distance between fixtures) determine
  // what the readings may not, as they do in calibrate.
  append_constraint_rows(problem, problem.initial_free_parameters(), J, &residuals);
  Identifiability a = analyze_identifiability(J, problem.parameter_names(), id_options, turns);
  if (with_prior) {
    // Before measuring, the noise is as the model states it (sigma = 1 in whitened units).
    const VectorXd precision = model_prior(problem).precision();
    add_prior(a, J, precision, data_share(J, precision), id_options, turns);
  }
  // An imported arm's calibration chooses its free set from the data (calibrate): say here
  // what it would keep and why it would fix the rest.
  std::vector<std::string> kept_names, null_directions;
  if (a.rank_deficient() && !with_prior && !vm.count("free") && !vm.count("fix") &&
      model->mechanism().type() == "urdf-arm") {
    const std::vector<int> keep = choose_identifiable(*model, free, J, id_options, turns);
    for (int k : keep) kept_names.push_back(problem.parameter_names()[static_cast<std::size_t>(k)]);
    for (const DependentParameter& d :
         dependent_parameters(J, problem.parameter_names(), keep, id_options, turns))
      null_directions.push_back(describe_dependent(d, *model));
  }
  const std::optional<SensitivityResult> sensitivity =
      sensitivity_from_options(vm, model, values, data, free);
  const bool json_to_stdout = (vm.count("json") && plan.to_stdout("--json")) ||
                              (vm.count("html") && plan.to_stdout("--html"));
  if (!json_to_stdout) {
    out() << data.size() << " configurations\n" << to_text(a);
    if (with_prior) {
      out() << "determined by the data / by the prior (1 - posterior var / prior var, at "
               "the stated reading_std):\n";
      for (int i = 0; i < a.data_share.size(); ++i)
        out() << format_text("  %-24s data %5.1f %%  prior %5.1f %%\n", a.names[i].c_str(),
                             100 * a.data_share[i], 100 * (1 - a.data_share[i]));
    }
    if (a.num_residuals < a.num_parameters)
      out() << "fewer readings (" << a.num_residuals << ") than free parameters ("
            << a.num_parameters << "): measure more configurations\n";
    if (!kept_names.empty()) {
      out() << "an arm imported from a URDF: calibrate (without --free/--fix) keeps "
            << kept_names.size() << " of the " << free.size()
            << " free parameters and fixes the others, each a duplicate of kept ones:\n";
      for (const auto& line : null_directions) out() << "  " << line << "\n";
    }
    if (sensitivity) out() << sensitivity_text(*sensitivity);
  }
  if (vm.count("json") || vm.count("html")) {
    nlohmann::ordered_json out = json_document("kincal-observability");
    out["model"] = vm.count("model") ? vm["model"].as<std::string>() : "";
    out["source"] = vm.count("data") ? vm["data"].as<std::string>()
                                     : std::to_string(data.size()) + " random configurations";
    out["configurations"] = data.size();
    out.update(to_json(a));
    if (sensitivity) out["sensitivity"] = sensitivity_json(*sensitivity);
    if (!kept_names.empty()) {
      out["calibrate_keeps"] = kept_names;
      out["null_directions"] = null_directions;
    }
    std::vector<std::pair<std::string, std::string>> outputs;
    if (vm.count("json")) outputs.push_back({"--json", out.dump(2) + "\n"});
    if (vm.count("html")) outputs.push_back({"--html", render_observability_html(out)});
    plan.write(outputs);
  }
  return 0;
}

}  // namespace kincal::cli
