#pragma once
// The name policy (names.hpp) applied to a whole model, whoever built it: a model file's
// reader, a preset's factory, a plug-in's type. Every name a model shows the world (its
// types, actuators, sensors, readings and parameters, the labels of its constraints) becomes
// a column of a measurement file, a cell of an exported CSV, a key of a report or text on a
// terminal (docs/reliability.md, "Names").

#include <string>

#include "kincal/framework/kinematics/measurement_model.hpp"

namespace kincal {

/// Empty when every name of `model` follows the policy; otherwise the first one that does
/// not, as "<what> '<name, escaped>' <problem>", e.g. "actuator '=cmd|...' starts with
/// '='...". Types and sensor names are names; actuators, readings and parameters are columns
/// (a suffix with a dot is allowed); a constraint's label is one line of text (text_problem).
std::string model_name_problem(const MeasurementModel& model);

}  // namespace kincal
