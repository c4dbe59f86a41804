#pragma once
// The pose-accuracy sections of the pages for people: the predicted pose error over the
// workspace as a table (one column per prediction: calibrated and nominal, or designed,
// random and nominal) and as a plot of the error at every sampled configuration, and the
// verdict against the user's --target (cli/target_accuracy.hpp).

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "kincal/cli/html_report.hpp"

namespace kincal::cli {

/// One prediction shown: its key in the JSON ("calibrated") and its label ("calibrated").
using PredictionColumn = std::pair<std::string, std::string>;

/// The table and the plot of a predicted pose error: `predicted` holds an object of figures
/// per column (position_rms_mm, position_mean_1sigma_mm, ..., orientation_max_95_rad) and,
/// for the plot, "position_1sigma_mm_per_sample": {column: [mm per sample]}. `target` is
/// the "target" object of target_json or null; its position is drawn as a line.
std::string pose_accuracy_html(const nlohmann::ordered_json& predicted,
                               const std::vector<PredictionColumn>& columns,
                               const nlohmann::ordered_json& target);

/// The calibration report's measured 3-D position error of the measured point (a point
/// tracker's): before calibration, registration only, calibrated, in-sample and held out
/// (--folds), as a table and a bar chart of the mean and max, and the error the parameters'
/// uncertainty predicts at the measured configurations. `r` is the report's JSON
/// ("position_error_mm", "cross_validation", "predicted_point_error_mm").
std::string measured_position_error_html(const nlohmann::ordered_json& r);

/// The verdict on a "target" object (target_json): good when met, a problem when not, a
/// note when it could not be judged; nullopt when `target` is not an object.
std::optional<Verdict> target_verdict(const nlohmann::ordered_json& target);

}  // namespace kincal::cli
