#pragma once
// What calibrate and observability say about parameters the data cannot tell apart: which
// ones to keep (an imported arm's preferences, models/urdf_arm.hpp) and, in words, what each
// of the others duplicates.

#include <string>
#include <vector>

#include "kincal/framework/analysis/identifiability.hpp"
#include "kincal/framework/kinematics/measurement_model.hpp"

namespace kincal {

/// A parameter's name in words: "shoulder_pan_joint.origin.rx" -> "shoulder_pan_joint's
/// origin, rotation about x".
std::string parameter_words(const std::string& name);

/// A parameter the data cannot tell from the others, in one sentence: what it duplicates, or
/// that no reading depends on it (and why, where the name says: a joint's offset whose axis
/// passes through the measured point, a rotation of the measured point about itself), and
/// when it takes a turn of the measurement frame to duplicate them, that too.
std::string describe_dependent(const DependentParameter& d, const MeasurementModel& model);

/// The sentence of describe_dependent after the parameter's name and words: "moves the
/// readings as +1 x base.x", "no reading depends on it (...)", "not determined".
std::string dependent_effect(const DependentParameter& d, const MeasurementModel& model);

/// The fixed parameters as one aligned table, one line each ("  name  in words  effect"),
/// under a header line: what calibrate prints instead of a note per parameter.
std::string fixed_parameters_table(const std::vector<std::string>& names,
                                   const std::vector<std::string>& effects);

/// The columns of J (the free parameters `free` of `model`) to keep: identifiable_subset, with
/// the model's identification_priority (an arm imported from a URDF states one), and the turns of
/// the measurement frame (measurement_frame_turns, rows as J's) that change no fit.
std::vector<int> choose_identifiable(const MeasurementModel& model, const std::vector<int>& free,
                                     const MatrixXd& J, const IdentifiabilityOptions& options,
                                     const MatrixXd& turns = MatrixXd());

}  // namespace kincal
