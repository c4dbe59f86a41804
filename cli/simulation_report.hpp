#pragma once
// Scenario options shared by `simulate` and `reproduce`, and the JSON form of one
// simulated calibration.

#include <nlohmann/json.hpp>
#include <string>

#include "kincal/cli/cli_util.hpp"
#include "kincal/framework/simulation.hpp"

namespace kincal::cli {

/// --case, --poses, --noise, --param-error, --config-range, --seed, --validation.
void add_scenario_options(po::options_description& options, bool with_case_and_poses);
/// ScenarioOptions from those options; `case_id` receives --case (0 when not given).
ScenarioOptions scenario_options_from(const po::variables_map& vm, int* case_id);

nlohmann::json to_json(const PoseErrorStats& stats);
nlohmann::json to_json(const Scenario& scenario, const CalibrationRun& run, int case_id);

/// Trace CSV: one row per solver iteration with cost and validation errors.
std::string trace_csv(const CalibrationRun& run);

}  // namespace kincal::cli
