#pragma once
// Scenario options shared by `simulate` and `reproduce` (the JSON form of one simulated
// calibration is the library's: framework/workflows/simulate.hpp).

#include <nlohmann/json.hpp>
#include <string>

#include "kincal/cli/cli_util.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/kinematics/units.hpp"
#include "kincal/framework/workflows/simulate.hpp"

namespace kincal::cli {

/// --case, --poses, --noise, --param-error, --config-range, --seed, --validation; the
/// quantities are given per unit ("5mm,0.01rad"; a bare number is mm).
void add_scenario_options(po::options_description& options, bool with_case_and_poses);
/// The per-unit value of `option` ("5mm,0.01rad"); throws CliError naming the option.
UnitValues unit_values_option(const po::variables_map& vm, const std::string& option);
/// ScenarioOptions from those options; `case_id` receives --case (0 when not given).
ScenarioOptions scenario_options_from(const po::variables_map& vm, int* case_id);

}  // namespace kincal::cli
