#pragma once
// The "Sensitivity to fixed parameters" section of the pages for people (the calibration
// report with calibrate --sensitivity, the observability page with --sensitivity): for each
// fixed parameter, the pose error an error in it leaves after calibrating the free ones, as
// a bar chart and a table.

#include <nlohmann/json.hpp>
#include <string>

namespace kincal::cli {

/// `rows`: the JSON of sensitivity_json (cli/sensitivity_option.hpp), one object per fixed
/// parameter. `target_mm` (NaN: none) is drawn as a line on the chart.
std::string sensitivity_html(const nlohmann::ordered_json& rows, double target_mm);

}  // namespace kincal::cli
