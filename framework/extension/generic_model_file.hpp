#pragma once
// A model-file reader and writer driven by a type's parameter list, for types whose object
// is just their parameters (and a few numeric options): most sensors. The keys follow from
// the parameter names relative to the component (after "<sensor name>."):
//   "offset" (mm)                           -> "offset": 0.3             (in its unit)
//   "tilt" (rad)                            -> "tilt_deg": 1.5           (degrees)
//   "base.x", "base.y", "base.z"            -> "base": [x, y, z]         (in their unit)
//   "frame.x" ... "frame.z", "frame.rx" ... "frame.rz" (mm, rad)
//                                           -> "frame": {"position": [x, y, z],
//                                                        "rotation_zyx_deg": [rx, ry, rz]}
// in the order of the parameters, after "name" (sensors), then the options. A type whose
// parameters do not group this way is refused when registered (std::logic_error); it writes
// its own reader and writer, as the mechanisms do. Bad input fails through JsonPath::fail,
// one line naming the key and where it is.

#include <functional>
#include <map>
#include <set>

#include "kincal/framework/extension/model_registry.hpp"

namespace kincal {

/// A number read from the object besides the parameters, e.g. a sensor's range.
struct ModelFileOption {
  std::string key;
  double default_value = 0;  ///< when the key is absent
};
/// Option values by key.
using ModelFileOptions = std::map<std::string, double>;

/// What a generic reader needs to know of a type: its parameters (names relative to the
/// component, units, nominal values used for optional keys), which keys may be absent, and
/// its options.
struct ModelFileLayout {
  std::vector<Parameter> parameters;
  std::set<std::string> optional_keys;
  std::vector<ModelFileOption> options;
};

/// The layout of `prototype`'s parameters, names relative to "<prototype.name()>.".
ModelFileLayout sensor_layout(const Sensor& prototype, std::set<std::string> optional_keys = {},
                              std::vector<ModelFileOption> options = {});

/// A sensor type read and written by `layout`: `make` builds a sensor of that name with
/// those nominal values (in layout order) and options; `options_of` gives back a sensor's
/// options for writing (may be empty when there are none). Throws std::logic_error when a
/// parameter group has no file form.
SensorType generic_sensor_type(
    std::string type, std::string description, ModelFileLayout layout,
    std::function<std::shared_ptr<const Sensor>(const std::string& name, const VectorXd& nominal,
                                                const ModelFileOptions& options)>
        make,
    std::function<ModelFileOptions(const Sensor&)> options_of = nullptr);

/// The same for a mechanism (no "name"; parameter names as they are).
MechanismType generic_mechanism_type(
    std::string type, std::string description, ModelFileLayout layout,
    std::function<std::shared_ptr<const Mechanism>(const VectorXd& nominal,
                                                   const ModelFileOptions& options)>
        make,
    std::function<ModelFileOptions(const Mechanism&)> options_of = nullptr);

}  // namespace kincal
