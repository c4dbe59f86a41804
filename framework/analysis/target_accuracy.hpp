#pragma once
// A pose accuracy a user needs (calibrate, validate and design --target) and its comparison
// with a predicted or measured pose error, as data: the text, the JSON ("target") and the
// page render the same judgement.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "kincal/framework/analysis/pose_accuracy.hpp"
#include "kincal/framework/analysis/position_error.hpp"

namespace kincal {

/// The accuracy asked for: a position error in mm and, optionally, an orientation error in
/// rad.
struct TargetAccuracy {
  double position_mm = 0;
  double orientation_rad = 0;
  bool has_orientation = false;
  /// "0.1 mm" or "0.1 mm and 0.001 rad", for messages.
  std::string to_string() const;
};

/// "0.1mm" or "0.1mm,0.05deg" (a length with its unit, optionally an angle): the program's
/// --target, Python's target=. Throws std::invalid_argument "<label> '<text>': ..." when it is
/// not one positive length with an optional positive angle (a bare number, which would be
/// taken as mm, included: an accuracy says its unit).
TargetAccuracy parse_target_accuracy(const std::string& text, const std::string& label);

/// The target compared with an error figure.
struct TargetJudgement {
  TargetAccuracy target;
  std::string compared_with;  ///< what the figures are
  /// The figures compared (NaN when not known).
  double position_mm = NAN, orientation_rad = NAN;
  /// nullopt when the position figure is missing (not computed, or not a number).
  std::optional<bool> meets;
  /// One sentence: "meets the 0.1 mm target: ...", "does not meet ...", "cannot say ...".
  std::string verdict;
};

/// Compares `position_mm` (and `orientation_rad` when the target has an angle; NaN when the
/// figure is not known) with the target. `figure` names what the numbers are, e.g.
/// "predicted position error (95 % quantile, worst configuration of the workspace)".
/// `why_missing` is the reason given when the position figure is not a number.
TargetJudgement judge_target(const TargetAccuracy& target, double position_mm,
                             double orientation_rad, const std::string& figure,
                             const std::string& why_missing);

/// The target against a predicted pose error over the workspace: its 95 % quantile at the
/// worst sampled configuration (calibrate: the estimate's, when computed; design: the
/// designed configurations').
TargetJudgement judge_predicted_target(const TargetAccuracy& target,
                                       const AccuracyComparison& predicted);
TargetJudgement judge_predicted_target(const TargetAccuracy& target,
                                       const PoseErrorPrediction& predicted);

/// The target against measured held-out errors: the largest 3-D position error of the
/// measured point (`after`), or not judged when the readings measure no point (`after`
/// null), with `why_not`.
TargetJudgement judge_measured_target(const TargetAccuracy& target, const PositionErrorStats* after,
                                      const std::string& why_not);

/// {"position_mm", "orientation_rad", "compared_with", "position_mm_figure",
///  "orientation_rad_figure", "meets" (null when not judged), "verdict"}.
nlohmann::ordered_json to_json(const TargetJudgement& judgement);

}  // namespace kincal
