#include "kincal/cli/simulation_report.hpp"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "kincal/cli/shared_options.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal::cli {

void add_scenario_options(po::options_description& options, bool with_case_and_poses) {
  if (with_case_and_poses) {
    options.add_options()("case", po::value<int>(),
                          "paper's Table 2 case 1..5 (sets --noise-half-width and --poses)")(
        "poses", po::value<int>(), "number of measured configurations (default 30)")(
        "noise-half-width", po::value<std::string>(),
        "reading noise as the paper states it, a half-width a per unit, e.g. 0.00125mm or "
        "0.05mm,1e-4rad: each reading gets U[-a, a] (default 0; a bare number is mm; "
        "--noise-std states the same noise as its std, a / sqrt(3))");
    add_deprecated_alias(options, "noise", "noise-half-width", po::value<std::string>());
  }
  options.add_options()("param-error", po::value<std::string>()->default_value("5mm,0.01rad"),
                        "true parameters = nominal + U[-e, e] on each free parameter, e per "
                        "unit (a parameter's own param_error in the model file wins); 0 is "
                        "zero in every unit: the model is the truth")(
      "seed", po::value<Seed>()->default_value(Seed{1}, "1"), "random seed")(
      "validation", po::value<int>()->default_value(200),
      "validation configurations for the pose errors");
  add_config_range_option(options);
}

UnitValues unit_values_option(const po::variables_map& vm, const std::string& option) {
  const std::string text = vm[option].as<std::string>();
  UnitValues values;
  try {
    values = UnitValues::parse(text);
  } catch (const std::invalid_argument& e) {
    throw CliError(option_flag(option) + " '" + text + "': " + e.what());
  }
  for (const auto& [unit, value] : values.values())
    if (!(value >= 0))
      throw CliError(option_flag(option) + " '" + text + "': expected values >= 0");
  return values;
}

ScenarioOptions scenario_options_from(const po::variables_map& vm, int* case_id) {
  ScenarioText text;
  if (vm.count("case")) text.case_id = vm["case"].as<int>();
  if (vm.count("poses")) text.poses = vm["poses"].as<int>();
  if (vm.count("noise-half-width"))
    text.noise_half_width = vm["noise-half-width"].as<std::string>();
  if (vm.count("noise-std")) text.noise_std = vm["noise-std"].as<std::string>();
  text.param_error = vm["param-error"].as<std::string>();
  if (vm.count("config-range")) text.config_range = vm["config-range"].as<std::string>();
  text.seed = vm["seed"].as<Seed>().value;
  text.validation = vm["validation"].as<int>();
  *case_id = text.case_id;
  try {
    return scenario_options(text, "--");
  } catch (const std::invalid_argument& e) {
    throw CliError(e.what());
  }
}

}  // namespace kincal::cli
