// kincal observability: identifiability of a model's free parameters from a measurement
// file or from simulated configurations, before any solving.

#include <cmath>
#include <cstdio>
#include <iostream>

#include "kincal/cli/memory_check.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/cli/simulation_report.hpp"
#include "kincal/framework/calibration_report.hpp"
#include "kincal/framework/prior_problem.hpp"
#include "kincal/framework/simulation.hpp"

namespace kincal::cli {

int run_observability(const Args& args) {
  po::options_description options("kincal observability");
  options.add_options()("model", po::value<std::string>(), "model file (JSON)")(
      "data", po::value<std::string>(), "measurement file (CSV) whose configurations to analyse")(
      "poses", po::value<int>(),
      "instead of --data: this many random configurations, home actuator values + U[-r, r]")(
      "seed", po::value<Seed>()->default_value(Seed{1}, "1"), "random seed for --poses")(
      "config-range", po::value<std::string>(),
      "r per unit for --poses, e.g. 20mm,0.5rad (default: each actuator's range in the model)")(
      "rcond", po::value<double>()->default_value(IdentifiabilityOptions{}.rcond),
      "numerical rank threshold relative to the largest scaled singular value")(
      "skip-bad-rows", po::bool_switch(), "drop rows the model cannot reach instead of failing")(
      "json", po::value<std::string>(), "write the analysis as JSON to FILE, or - for stdout");
  add_free_fix_options(options);
  add_prior_std_option(options);
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
  plan.check();

  std::shared_ptr<MeasurementModel> model = load_model_option(vm);
  apply_free_fix(vm, *model);
  apply_prior_std(vm, *model);
  const bool with_prior =
      check_prior_usable(*model, vm.count("model") ? vm["model"].as<std::string>() : "the model");
  const VectorXd values = model->parameters().nominal_values();
  const std::vector<int> free = model->parameters().free_indices();
  if (free.empty()) throw CliError("no free parameters: nothing to analyse (use --free)");

  Measurements data;
  if (vm.count("data")) {
    data = load_measurements("observability", vm["data"].as<std::string>(), *model, values,
                             vm["skip-bad-rows"].as<bool>(), vm["model"].as<std::string>())
               .data;
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
  Identifiability a = analyze_identifiability(J, problem.parameter_names(), id_options);
  if (with_prior) {
    // Before measuring, the noise is as the model states it (sigma = 1 in whitened units).
    const VectorXd precision = model_prior(problem).precision();
    add_prior(a, J, precision, data_share(J, precision), id_options);
  }
  const bool json_to_stdout = vm.count("json") && plan.to_stdout("--json");
  if (!json_to_stdout) {
    std::cout << data.size() << " configurations\n" << to_text(a);
    if (with_prior) {
      std::cout << "determined by the data / by the prior (1 - posterior var / prior var, at "
                   "the stated reading_std):\n";
      for (int i = 0; i < a.data_share.size(); ++i)
        std::printf("  %-24s data %5.1f %%  prior %5.1f %%\n", a.names[i].c_str(),
                    100 * a.data_share[i], 100 * (1 - a.data_share[i]));
    }
    if (a.num_residuals < a.num_parameters)
      std::cout << "fewer readings (" << a.num_residuals << ") than free parameters ("
                << a.num_parameters << "): measure more configurations\n";
  }
  if (vm.count("json")) plan.write({{"--json", to_json(a).dump(2) + "\n"}});
  return 0;
}

}  // namespace kincal::cli
