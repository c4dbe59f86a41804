#include "kincal/cli/target_accuracy.hpp"

#include <cmath>
#include <stdexcept>

#include "kincal/cli/commands.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal::cli {

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

}  // namespace kincal::cli
