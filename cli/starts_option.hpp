#pragma once
// --starts N of calibrate and simulate: the solve from N starting values drawn from the free
// parameters' tolerances (framework/calibration/multi_start.hpp); the report's words for the
// minima they end in are framework/analysis/starts_report.hpp's.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "kincal/cli/cli_util.hpp"
#include "kincal/framework/analysis/starts_report.hpp"

namespace kincal::cli {

/// Starts when --starts is not given (docs/benchmarks.md, "Local minima", measures it).
constexpr int kDefaultStarts = 1;

/// Adds --starts N.
void add_starts_option(po::options_description& options);
/// --starts, checked (1 to 10000).
int starts_option(const po::variables_map& vm);

}  // namespace kincal::cli
