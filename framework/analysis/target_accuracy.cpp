#include "kincal/framework/analysis/target_accuracy.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "kincal/framework/kinematics/units.hpp"

namespace kincal {

namespace {

std::string figure_text(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

nlohmann::ordered_json number(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json();
}

// A figure as the JSON carries it: not a number (null there) is NaN.
double finite_or_nan(double v) { return std::isfinite(v) ? v : NAN; }

const char* const kPredictedFigure =
    "predicted pose error (95 % quantile at the worst sampled configuration of the workspace)";

}  // namespace

TargetAccuracy parse_target_accuracy(const std::string& text, const std::string& label) {
  const std::string expected =
      "; expected a length with its unit, e.g. 0.1mm, optionally with "
      "an angle, e.g. 0.1mm,0.05deg";
  UnitValues values;
  try {
    values = UnitValues::parse(text);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(label + " '" + text + "': " + e.what() + expected);
  }
  if (text.find("mm") == std::string::npos || !values.has(kMillimetre))
    throw std::invalid_argument(label + " '" + text + "': no length in mm" + expected);
  TargetAccuracy target;
  target.position_mm = values.get(kMillimetre);
  target.has_orientation = values.has(kRadian);
  target.orientation_rad = values.get(kRadian, 0);
  if (!(target.position_mm > 0) || !std::isfinite(target.position_mm) ||
      (target.has_orientation &&
       (!(target.orientation_rad > 0) || !std::isfinite(target.orientation_rad))))
    throw std::invalid_argument(label + " '" + text +
                                "': the accuracy must be positive and finite" + expected);
  return target;
}

std::string TargetAccuracy::to_string() const {
  std::string out = figure_text(position_mm) + " mm";
  if (has_orientation) out += " and " + figure_text(orientation_rad) + " rad";
  return out;
}

TargetJudgement judge_target(const TargetAccuracy& target, double position_mm,
                             double orientation_rad, const std::string& figure,
                             const std::string& why_missing) {
  TargetJudgement v;
  v.target = target;
  v.compared_with = figure;
  v.position_mm = position_mm;
  v.orientation_rad = orientation_rad;
  const std::string of_target = "the " + target.to_string() + " target";
  if (!std::isfinite(position_mm)) {
    v.verdict = "cannot say whether the pose meets " + of_target + ": " + why_missing;
    return v;
  }
  std::string numbers = figure + " " + figure_text(position_mm) + " mm";
  bool meets = position_mm <= target.position_mm;
  if (target.has_orientation) {
    if (std::isfinite(orientation_rad)) {
      numbers += " and " + figure_text(orientation_rad) + " rad";
      meets = meets && orientation_rad <= target.orientation_rad;
    } else {
      numbers += " (the orientation error is not known here: only the position is judged)";
    }
  }
  v.meets = meets;
  v.verdict = (meets ? "meets " : "does not meet ") + of_target + ": " + numbers;
  return v;
}

TargetJudgement judge_predicted_target(const TargetAccuracy& target,
                                       const AccuracyComparison& predicted) {
  if (!predicted.computed)
    return judge_target(target, NAN, NAN, kPredictedFigure,
                        "the pose error was not predicted (" + predicted.why_not + ")");
  return judge_predicted_target(target, predicted.calibrated);
}

TargetJudgement judge_predicted_target(const TargetAccuracy& target,
                                       const PoseErrorPrediction& predicted) {
  return judge_target(target, finite_or_nan(predicted.position_max_95),
                      finite_or_nan(predicted.orientation_max_95), kPredictedFigure,
                      "the pose error was not predicted");
}

TargetJudgement judge_measured_target(const TargetAccuracy& target, const PositionErrorStats* after,
                                      const std::string& why_not) {
  return judge_target(target, after ? finite_or_nan(after->max) : NAN, NAN,
                      "largest held-out 3-D position error of the measured point", why_not);
}

nlohmann::ordered_json to_json(const TargetJudgement& j) {
  const TargetAccuracy& target = j.target;
  return {{"position_mm", target.position_mm},
          {"orientation_rad",
           target.has_orientation ? number(target.orientation_rad) : nlohmann::ordered_json()},
          {"compared_with", j.compared_with},
          {"position_mm_figure", number(j.position_mm)},
          {"orientation_rad_figure", number(j.orientation_rad)},
          {"meets", j.meets ? nlohmann::ordered_json(*j.meets) : nlohmann::ordered_json()},
          {"verdict", j.verdict}};
}

}  // namespace kincal
