#pragma once
// Ready-made serial arms from published DH tables, each with a tracker and a default free
// mask that a default simulation determines (redundant parameters fixed).

#include <memory>
#include <string>

#include "kincal/framework/kinematics/measurement_model.hpp"

namespace kincal {

/// Unimation PUMA 560 with a laser tracker (point-tracker): 27 free parameters.
std::shared_ptr<MeasurementModel> make_puma560();
std::string puma560_description();

/// Universal Robots UR5 (CB3) with an optical tracker (pose-tracker): 30 free parameters.
std::shared_ptr<MeasurementModel> make_ur5();
std::string ur5_description();

}  // namespace kincal
