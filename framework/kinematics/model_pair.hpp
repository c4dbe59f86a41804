#pragma once
// Two model files of one machine: a known truth and a model (simulate --truth, compare).
// They must describe the same parameters, actuators and readings, in the same order, so that
// their values can be compared or one's values used as the other's truth.

#include <string>

#include "kincal/framework/kinematics/measurement_model.hpp"

namespace kincal {

/// Throws std::invalid_argument "<a_label> and <b_label> do not have the same parameters: <the
/// first difference>" (one line) unless `a` and `b` have the same parameter names and units, the
/// same actuators and the same readings, in the same order.
void check_same_parameters(const MeasurementModel& a, const std::string& a_label,
                           const MeasurementModel& b, const std::string& b_label);

}  // namespace kincal
