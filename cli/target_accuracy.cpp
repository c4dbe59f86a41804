#include "kincal/cli/target_accuracy.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "kincal/cli/commands.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal::cli {

namespace {

std::string figure_text(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

nlohmann::ordered_json number(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json();
}

}  // namespace

std::string TargetAccuracy::to_string() const {
  std::string out = figure_text(position_mm) + " mm";
  if (has_orientation) out += " and " + figure_text(orientation_rad) + " rad";
  return out;
}

void add_target_option(po::options_description& options) {
  options.add_options()(
      "target", po::value<std::string>(),
      "the pose accuracy you need, a length with its unit and optionally an angle, e.g. 0.1mm "
      "or 0.1mm,0.05deg: the verdicts say whether the pose error meets it");
}

std::optional<TargetAccuracy> target_option(const po::variables_map& vm) {
  if (!vm.count("target")) return std::nullopt;
  const std::string text = vm["target"].as<std::string>();
  const std::string expected =
      "; expected a length with its unit, e.g. 0.1mm, optionally with "
      "an angle, e.g. 0.1mm,0.05deg";
  UnitValues values;
  try {
    values = UnitValues::parse(text);
  } catch (const std::invalid_argument& e) {
    throw CliError("--target '" + text + "': " + e.what() + expected);
  }
  // A bare number would be taken as mm (UnitValues' old default): an accuracy says its unit.
  if (text.find("mm") == std::string::npos || !values.has(kMillimetre))
    throw CliError("--target '" + text + "': no length in mm" + expected);
  TargetAccuracy target;
  target.position_mm = values.get(kMillimetre);
  target.has_orientation = values.has(kRadian);
  target.orientation_rad = values.get(kRadian, 0);
  if (!(target.position_mm > 0) || !std::isfinite(target.position_mm) ||
      (target.has_orientation &&
       (!(target.orientation_rad > 0) || !std::isfinite(target.orientation_rad))))
    throw CliError("--target '" + text + "': the accuracy must be positive and finite" + expected);
  return target;
}

TargetVerdict judge_target(const TargetAccuracy& target, double position_mm, double orientation_rad,
                           const std::string& figure, const std::string& why_missing) {
  TargetVerdict v;
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

nlohmann::ordered_json target_json(const TargetAccuracy& target, const TargetVerdict& verdict,
                                   const std::string& figure, double position_mm,
                                   double orientation_rad) {
  return {
      {"position_mm", target.position_mm},
      {"orientation_rad",
       target.has_orientation ? number(target.orientation_rad) : nlohmann::ordered_json()},
      {"compared_with", figure},
      {"position_mm_figure", number(position_mm)},
      {"orientation_rad_figure", number(orientation_rad)},
      {"meets", verdict.meets ? nlohmann::ordered_json(*verdict.meets) : nlohmann::ordered_json()},
      {"verdict", verdict.verdict}};
}

namespace {

double number_at(const nlohmann::ordered_json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_number() ? j[key].get<double>() : NAN;
}

nlohmann::ordered_json judged(const TargetAccuracy& target, double position, double orientation,
                              const std::string& figure, const std::string& why_missing) {
  return target_json(target, judge_target(target, position, orientation, figure, why_missing),
                     figure, position, orientation);
}

}  // namespace

nlohmann::ordered_json predicted_target(const TargetAccuracy& target,
                                        const nlohmann::ordered_json& predicted_pose_error,
                                        const std::string& which) {
  const nlohmann::ordered_json& p = predicted_pose_error;
  const nlohmann::ordered_json none;
  const nlohmann::ordered_json& figures = p.is_object() && p.contains(which) ? p[which] : none;
  std::string why = "the pose error was not predicted";
  if (p.is_object() && p.contains("why_not") && p["why_not"].is_string())
    why += " (" + p["why_not"].get<std::string>() + ")";
  return judged(target, number_at(figures, "position_max_95_mm"),
                number_at(figures, "orientation_max_95_rad"),
                "predicted pose error (95 % quantile at the worst sampled configuration of the "
                "workspace)",
                why);
}

nlohmann::ordered_json measured_target(const TargetAccuracy& target,
                                       const nlohmann::ordered_json& position_error,
                                       const std::string& why_not) {
  const nlohmann::ordered_json none;
  const nlohmann::ordered_json& after =
      position_error.is_object() && position_error.contains("after") ? position_error["after"]
                                                                     : none;
  return judged(target, number_at(after, "max"), NAN,
                "largest held-out 3-D position error of the measured point", why_not);
}

}  // namespace kincal::cli
