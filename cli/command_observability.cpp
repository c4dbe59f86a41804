// kincal observability: identifiability of a model's free parameters from a measurement
// file or from simulated configurations, before any solving.

#include <cmath>
#include <cstdio>
#include <iostream>

#include "kincal/cli/common_options.hpp"
#include "kincal/cli/identifiability_words.hpp"
#include "kincal/cli/memory_check.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/cli/shared_options.hpp"
#include "kincal/cli/simulation_report.hpp"
#include "kincal/framework/calibration_report.hpp"
#include "kincal/framework/fixed_parameter_sensitivity.hpp"
#include "kincal/framework/prior_problem.hpp"
#include "kincal/framework/simulation.hpp"

namespace kincal::cli {

namespace {

// The sensitivity table: what an error in each fixed parameter leaves after calibration.
std::string sensitivity_text(const SensitivityResult& s) {
  std::string out =
      "sensitivity to fixed parameters (each one off by the step below, the free ones "
      "re-calibrated; first order):\n";
  char buf[200];
  std::snprintf(buf, sizeof buf, "  %-22s %10s %14s %12s %12s %14s %14s\n", "parameter", "error",
                "residual RMS", "pos. mean", "pos. max", "orient. mean", "orient. max");
  out += buf;
  std::snprintf(buf, sizeof buf, "  %-22s %10s %14s %12s %12s %14s %14s\n", "", "", "(readings)",
                "(mm)", "(mm)", "(mrad)", "(mrad)");
  out += buf;
  for (const auto& r : s.rows) {
    char error[40];
    if (r.unit == kRadian)
      std::snprintf(error, sizeof error, "%g mrad", r.delta * 1000);
    else
      std::snprintf(error, sizeof error, "%g %s", r.delta, r.unit.c_str());
    std::snprintf(buf, sizeof buf, "  %-22s %10s %14.3g %12.4g %12.4g %14.4g %14.4g\n",
                  r.name.c_str(), error, r.residual_rms, r.position_mean, r.position_max,
                  r.orientation_mean * 1000, r.orientation_max * 1000);
    out += buf;
  }
  if (s.free_rank < s.num_free)
    out += "  (the free parameters are rank deficient: " + std::to_string(s.free_rank) + " of " +
           std::to_string(s.num_free) +
           " determined; the re-calibration takes the smallest correction)\n";
  return out;
}

nlohmann::ordered_json sensitivity_json(const SensitivityResult& s) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const auto& r : s.rows)
    rows.push_back({{"name", r.name},
                    {"unit", r.unit},
                    {"error", r.delta},
                    {"residual_rms", r.residual_rms},
                    {"position_mean_mm", r.position_mean},
                    {"position_max_mm", r.position_max},
                    {"orientation_mean_rad", r.orientation_mean},
                    {"orientation_max_rad", r.orientation_max}});
  return rows;
}

}  // namespace

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
      "skip-bad-rows", po::bool_switch(), "drop rows the model cannot reach instead of failing")(
      "sensitivity", po::bool_switch(),
      "also: for each fixed parameter, the pose error an error in it leaves after calibrating "
      "the free ones (over the same configurations)")(
      "sensitivity-step", po::value<std::string>()->default_value("1mm,0.001rad"),
      "the error assumed in each fixed parameter, per unit");
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
    data = load_measurements("observability", vm["data"].as<std::string>(), *model, values,
                             vm["skip-bad-rows"].as<bool>(), vm["model"].as<std::string>(),
                             data_limits(vm))
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
  // An imported arm's calibration chooses its free set from the data (calibrate): say here
  // what it would keep and why it would fix the rest.
  std::vector<std::string> kept_names, null_directions;
  if (a.rank_deficient() && !with_prior && !vm.count("free") && !vm.count("fix") &&
      model->mechanism().type() == "urdf-arm") {
    const std::vector<int> keep = choose_identifiable(*model, free, J, id_options);
    for (int k : keep) kept_names.push_back(problem.parameter_names()[static_cast<std::size_t>(k)]);
    for (const DependentParameter& d :
         dependent_parameters(J, problem.parameter_names(), keep, id_options))
      null_directions.push_back(describe_dependent(d, *model));
  }
  SensitivityResult sensitivity;
  const bool want_sensitivity = vm["sensitivity"].as<bool>();
  if (want_sensitivity) {
    const UnitValues step = unit_values_option(vm, "sensitivity-step");
    try {
      sensitivity = fixed_parameter_sensitivity(
          model, values, data, data, free, step.get(kMillimetre, 1.0), step.get(kRadian, 1e-3));
    } catch (const std::runtime_error& e) {
      throw CliError(std::string("--sensitivity: ") + e.what());
    }
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
    if (!kept_names.empty()) {
      std::cout << "an arm imported from a URDF: calibrate (without --free/--fix) keeps "
                << kept_names.size() << " of the " << free.size()
                << " free parameters and fixes the others, each a duplicate of kept ones:\n";
      for (const auto& line : null_directions) std::cout << "  " << line << "\n";
    }
    if (want_sensitivity) std::cout << sensitivity_text(sensitivity);
  }
  if (vm.count("json")) {
    nlohmann::ordered_json out = json_document("kincal-observability");
    out.update(to_json(a));
    if (want_sensitivity) out["sensitivity"] = sensitivity_json(sensitivity);
    if (!kept_names.empty()) {
      out["calibrate_keeps"] = kept_names;
      out["null_directions"] = null_directions;
    }
    plan.write({{"--json", out.dump(2) + "\n"}});
  }
  return 0;
}

}  // namespace kincal::cli
