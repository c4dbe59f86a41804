#pragma once
// The readings' noise and the parameters' priors as a user writes them, with their units:
// "0.0007mm" or "0.05mm,1e-4rad" for the noise per reading unit; "2.887mm,0.0058rad",
// "leg*.base.z=0.5mm" or "gauge.offset=0.1" for priors. One parser and one way to apply each,
// for every face (the command line's --noise-std and --prior-std, Python's noise_std= and
// prior_std=, a project file). Errors are std::invalid_argument naming the item; the caller
// adds where it came from (an option, a keyword).

#include <string>
#include <vector>

#include "kincal/framework/kinematics/measurement_model.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal {

/// One item of a prior specification.
struct PriorStdRule {
  std::string pattern;  ///< parameters whose name matches this glob; "" = every free one in `unit`
  double value = 0;     ///< the std, > 0, in `unit`
  std::string unit;     ///< the unit; "" = the parameter's own unit (a pattern without one)
};

/// "2.887mm,0.0058rad", "leg*.base.z=0.5mm", "gauge.offset=0.1", or a mix, comma-separated:
/// a number with a unit applies to every free parameter in that unit (a bare number is mm, as
/// everywhere), PATTERN=STD to the parameters matching PATTERN (STD in the parameter's unit
/// when it has none; deg is converted to rad). Throws std::invalid_argument naming the item.
std::vector<PriorStdRule> parse_prior_std(const std::string& spec);

/// Whether every rule is per unit (no pattern).
bool prior_std_per_unit_only(const std::vector<PriorStdRule>& rules);

/// Sets the prior std of the parameters each rule names, in order (later rules win), replacing
/// the model's. Throws std::invalid_argument when a pattern matches nothing ("'leg9*' matches
/// no parameter of the model") or a parameter in another unit than the rule's.
void apply_prior_std(const std::vector<PriorStdRule>& rules, MeasurementModel& model);

/// Whether a free parameter of `model` has a prior. When one has, the model must state its
/// readings' noise (reading_std, or --noise-std / noise_std=): the prior weighs against
/// whitened residuals. Throws std::invalid_argument naming `model_file` otherwise.
bool check_prior_usable(const MeasurementModel& model, const std::string& model_file);

/// The noise std of each reading of `model` from values per unit (every reading's unit needs
/// one, within [1e-9, 1e6] of it). Throws std::invalid_argument saying which reading lacks a
/// value or has one out of range (the caller prefixes the specification it came from).
VectorXd noise_std_per_reading(const UnitValues& noise, const MeasurementModel& model);

/// UnitValues::parse, and every value >= 0; throws std::invalid_argument otherwise.
UnitValues parse_non_negative_unit_values(const std::string& text);

}  // namespace kincal
