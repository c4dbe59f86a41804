#pragma once
// --starts N of calibrate and simulate: the solve from N starting values drawn from the free
// parameters' tolerances (framework/calibration/multi_start.hpp), the distinct minima they end in,
// and the report's words for them (text, JSON "starts", the HTML verdict).

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "kincal/cli/cli_util.hpp"
#include "kincal/framework/calibration/multi_start.hpp"

namespace kincal::cli {

/// Starts when --starts is not given (docs/benchmarks.md, "Local minima", measures it).
constexpr int kDefaultStarts = 1;

/// Adds --starts N.
void add_starts_option(po::options_description& options);
/// --starts, checked (1 to 10000).
int starts_option(const po::variables_map& vm);

/// One to a few lines for the terminal, each ending in "\n"; empty for a single start.
std::string starts_text(const StartsReport& report);
/// "starts": count, seed, spread_from, spread_assumed, best_start, unsolved, verdict
/// ("single_start", "one_minimum", "several_minima"), note, minima [{cost, starts,
/// distance_to_best}].
nlohmann::ordered_json starts_json(const StartsReport& report);

}  // namespace kincal::cli
