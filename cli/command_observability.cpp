// kincal observability: identifiability of a model's free parameters from a measurement
// file or from simulated configurations, before any solving.

#include <cmath>
#include <cstdio>
#include <iostream>

#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/memory_check.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/cli/project_record.hpp"
#include "kincal/cli/sensitivity_option.hpp"
#include "kincal/cli/shared_options.hpp"
#include "kincal/cli/simulation_report.hpp"
#include "kincal/framework/calibration/prior_and_noise.hpp"
#include "kincal/framework/report/pages.hpp"
#include "kincal/framework/workflows/observability.hpp"

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
  OutputPlan plan(console_output());
  for (const char* option : {"model", "data"})
    if (vm.count(option)) plan.input(std::string("--") + option, vm[option].as<std::string>());
  if (vm.count("json")) plan.output("--json", vm["json"].as<std::string>());
  if (vm.count("html")) plan.output("--html", vm["html"].as<std::string>());
  plan.check();

  std::shared_ptr<MeasurementModel> model = load_model_option(vm);
  apply_free_fix(vm, *model);
  apply_noise_std(vm, *model);
  apply_prior_std(vm, *model);
  ObservabilityRequest request;
  request.model_file = vm.count("model") ? vm["model"].as<std::string>() : "";
  request.identifiability = id_options;
  request.explicit_mask = vm.count("free") || vm.count("fix");
  // The model's own checks first (no free parameter, a prior without noise), before the data.
  check_prior_usable(*model, request.model_file.empty() ? "the model" : request.model_file);
  const VectorXd values = model->parameters().nominal_values();
  const int free = model->parameters().num_free();
  if (free == 0) throw CliError("no free parameters: nothing to analyse (use --free)");
  const std::size_t bytes_per_row = model->num_readings() * solve_bytes_per_row(free);
  if (vm.count("data")) {
    request.source = vm["data"].as<std::string>();
    const LoadedData loaded =
        load_measurements("observability", request.source, *model, values,
                          vm["skip-bad-rows"].as<bool>(), request.model_file, data_limits(vm));
    note_copied_rows("observability", loaded);
    request.data = loaded.data;
    check_memory(request.source, request.data.size(), bytes_per_row, "configuration");
  } else {
    const int poses = vm["poses"].as<int>();
    if (poses < 1) throw CliError("--poses must be at least 1");
    check_memory("--poses " + std::to_string(poses), poses, kConfigurationBytes + bytes_per_row,
                 "configuration");
    request.data = random_configurations(
        *model, poses, vm["seed"].as<Seed>().value,
        vm.count("config-range") ? unit_values_option(vm, "config-range") : UnitValues());
    request.source = std::to_string(request.data.size()) + " random configurations";
  }
  request.model = model;
  const ObservabilityResult result = observe(request);
  const std::optional<SensitivityResult> sensitivity =
      sensitivity_from_options(vm, model, values, request.data, model->parameters().free_indices());
  const bool json_to_stdout = (vm.count("json") && plan.to_stdout("--json")) ||
                              (vm.count("html") && plan.to_stdout("--html"));
  if (!json_to_stdout) {
    out() << observability_text(result);
    if (sensitivity) out() << sensitivity_text(*sensitivity);
  }
  if (vm.count("json") || vm.count("html")) {
    nlohmann::ordered_json extra = nlohmann::ordered_json::object();
    if (sensitivity) extra["sensitivity"] = to_json(*sensitivity);
    const nlohmann::ordered_json out = observability_json(result, extra);
    std::vector<std::pair<std::string, std::string>> outputs;
    if (vm.count("json")) outputs.push_back({"--json", json_report_text(out)});
    if (vm.count("html"))
      outputs.push_back({"--html", report::observability_html(result, sensitivity)});
    plan.write(outputs);
  }
  return 0;
}

}  // namespace kincal::cli
