#pragma once
// What a calibration's starts found (framework/calibration/multi_start.hpp), in words: the
// text and the JSON "starts" of the calibrate and simulate reports.

#include <nlohmann/json.hpp>
#include <string>

#include "kincal/framework/calibration/multi_start.hpp"

namespace kincal {

/// One to a few lines for the terminal, each ending in "\n"; empty for a single start.
std::string starts_text(const StartsReport& report);
/// "starts": count, seed, spread_from, spread_assumed, best_start, unsolved, verdict
/// ("single_start", "one_minimum", "several_minima"), note, minima [{cost, starts,
/// distance_to_best}].
nlohmann::ordered_json starts_json(const StartsReport& report);

}  // namespace kincal
