#pragma once
// Built-in models by name (`kincal list models`): shorthands over ModelRegistry::global().

#include <memory>
#include <string>
#include <vector>

#include "kincal/framework/kinematics/measurement_model.hpp"

namespace kincal {

struct PresetInfo {
  std::string name;
  std::string description;
};

/// Every registered preset, in registration order.
std::vector<PresetInfo> list_presets();

/// A fresh measurement model for a preset, with the preset's default free parameters.
/// Throws std::invalid_argument listing the presets when `name` is unknown.
std::shared_ptr<MeasurementModel> make_preset(const std::string& name);

/// The paper's hexapod (Table 1), home pose t0 = (0, 0, 410) mm, R0 = I, one length gauge,
/// with the paper's 24 free parameters.
std::shared_ptr<MeasurementModel> make_cube_hexapod();

/// A general 6-6 Gough-Stewart platform (Nategh & Agheli 2009, Table 1), home at zero
/// stroke, one length gauge, with the preset's free parameters (models/hexapod_presets.cpp).
std::shared_ptr<MeasurementModel> make_stewart_6_6();

}  // namespace kincal
