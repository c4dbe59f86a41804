#pragma once
// --target ACCURACY: the pose accuracy the user needs, e.g. 0.1mm, given
// as a length and optionally an angle (0.1mm,0.001rad or 0.1mm,0.05deg). calibrate, validate
// and design compare their predicted or measured pose error with it and say, in the text,
// the JSON ("target") and the page, whether it is met. The option is defined and parsed
// here only, so that the three commands agree on its spelling and meaning.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "kincal/cli/cli_util.hpp"

namespace kincal::cli {

/// The accuracy asked for: a position error in mm and, optionally, an orientation error in
/// rad (NaN when not given).
struct TargetAccuracy {
  double position_mm = 0;
  double orientation_rad = 0;
  bool has_orientation = false;
  /// "0.1 mm" or "0.1 mm and 0.001 rad", for messages.
  std::string to_string() const;
};

/// Adds --target to a command's options.
void add_target_option(po::options_description& options);

/// --target parsed; nullopt when not given. Throws CliError naming --target and the text
/// when it is not one positive length with an optional positive angle.
std::optional<TargetAccuracy> target_option(const po::variables_map& vm);

/// The comparison of an error figure with the target. `meets` is nullopt when the figure
/// is missing (not computed, or not a number), with `verdict` saying why.
struct TargetVerdict {
  std::optional<bool> meets;
  std::string verdict;  ///< one sentence: "meets the 0.1 mm target: ...", "does not meet ..."
};

/// Compares `position_mm` (and `orientation_rad` when the target has an angle; NaN when the
/// figure is not known) with the target. `figure` names what the numbers are, e.g.
/// "predicted position error (95 % quantile, worst configuration of the workspace)".
/// `why_missing` is the reason given when the position figure is not a number.
TargetVerdict judge_target(const TargetAccuracy& target, double position_mm, double orientation_rad,
                           const std::string& figure, const std::string& why_missing);

/// {"position_mm", "orientation_rad", "compared_with", "position_mm_figure",
///  "orientation_rad_figure", "meets" (null when not judged), "verdict"}.
nlohmann::ordered_json target_json(const TargetAccuracy& target, const TargetVerdict& verdict,
                                   const std::string& figure, double position_mm,
                                   double orientation_rad);

/// The target judged against a predicted pose error over the workspace (the JSON of
/// to_json(AccuracyComparison) or design's predicted_pose_error): its `which` prediction's
/// (e.g. "calibrated", "designed") 95 % quantile at the worst sampled configuration. Returns
/// the "target" object of target_json.
nlohmann::ordered_json predicted_target(const TargetAccuracy& target,
                                        const nlohmann::ordered_json& predicted_pose_error,
                                        const std::string& which);

/// The target judged against measured held-out errors: the largest 3-D position error of
/// the measured point (`position_error` holds "after": {"max", ...}), or not judged when the
/// readings measure no point (`position_error` null), with `why_not`.
nlohmann::ordered_json measured_target(const TargetAccuracy& target,
                                       const nlohmann::ordered_json& position_error,
                                       const std::string& why_not);

}  // namespace kincal::cli
