#pragma once
// Model files: a measurement model (mechanism, sensors, parameter values, free mask) as
// JSON, the format users edit and `kincal calibrate` writes back. Schema (docs/
// calibrating-a-machine.md has the full description):
//   { "format": "kincal-model", "version": 1, "units": "mm",
//     "mechanism": { "type": "hexapod-6ups",
//                    "home_pose": { "position": [x, y, z],
//                                   "rotation_zyx_deg": [rx, ry, rz] },
//                    "legs": [ { "name": "leg1", "base": [x, y, z],
//                                "platform": [x, y, z], "offset": 0 }, ... six ] },
//     "sensors": [ { "type": "length-gauge", "name": "gauge", "base": [...],
//                    "platform": [...], "offset": 0 } ],
//     "free": [ "leg4.base.x", ... ] }
// "free" lists the estimated parameters (names or glob patterns when written by hand);
// every other parameter is fixed. Rotations: R = Rz(rz) Ry(ry) Rx(rx), degrees.

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "kincal/framework/kinematics/measurement_model.hpp"

namespace kincal {

inline constexpr const char* kModelFormat = "kincal-model";
inline constexpr int kModelFormatVersion = 1;

/// The model with parameter values `values` (full vector, model layout) and the model's
/// free mask. Throws std::invalid_argument for mechanism or sensor types it cannot write,
/// and for a value that is not finite (a model file holds finite numbers only).
nlohmann::ordered_json model_to_json(const MeasurementModel& model, const VectorXd& values);

/// The model file of a calibration (model_to_json's text, indented): `values` at the estimate,
/// and only what it estimated listed as free: `fixed` names the free parameters the data
/// could not determine, fixed at their nominal values, so that the file calibrated again does
/// not stop on them.
std::string calibrated_model_text(MeasurementModel model, const VectorXd& values,
                                  const std::vector<std::string>& fixed);

/// A model whose nominal values are those of the file and whose free mask is its "free"
/// list. `source` names the file in messages ("<source>: mechanism.legs[2].base: expected
/// ..."). Throws std::invalid_argument.
std::shared_ptr<MeasurementModel> model_from_json(const nlohmann::ordered_json& j,
                                                  const std::string& source);

/// Reads and parses `path`. Every error is a one-line std::invalid_argument starting with
/// "<path>: " (with line/column for malformed JSON): a missing file, a directory, a read
/// error, a number out of range (1e999), or any schema violation of model_from_json.
std::shared_ptr<MeasurementModel> load_model(const std::string& path);

/// A model from the text of a model file, read as load_model reads the file (the size,
/// nesting and duplicate-key rules of framework/io/json_input.hpp, then model_from_json);
/// `source` names it in messages. Throws std::invalid_argument.
std::shared_ptr<MeasurementModel> model_from_text(const std::string& text,
                                                  const std::string& source);

/// A copy of `model` whose nominal values are `values`, same free mask.
std::shared_ptr<MeasurementModel> model_with_values(const MeasurementModel& model,
                                                    const VectorXd& values);

}  // namespace kincal
