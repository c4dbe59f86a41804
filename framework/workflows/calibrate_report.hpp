#pragma once
// The calibrate workflow's result as people read it (text) and as programs read it (JSON,
// format "kincal-calibration-report"): what `kincal calibrate` prints and writes with --json,
// and what its HTML page is rendered from. A caller's own sections (the program's --target
// and --sensitivity) go after the starts and before the verdict, in both.

#include <nlohmann/json.hpp>
#include <string>

#include "kincal/framework/workflows/calibrate.hpp"

namespace kincal {

/// The report, the starts, `extra_text` and the verdict.
std::string calibration_text(const CalibrateResult& result, const std::string& extra_text = "");

/// The report's JSON, then "starts", the members of `extra` (an object, or null), "verdict"
/// and, when parameters were fixed for the data, "null_directions".
nlohmann::ordered_json calibration_json(const CalibrateResult& result,
                                        const nlohmann::ordered_json& extra = nullptr);

}  // namespace kincal
