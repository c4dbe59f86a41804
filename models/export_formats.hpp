#pragma once
// A calibrated model in forms a controller or a robot description takes (kincal export):
//   urdf  serial arms: one joint per axis, its origin the calibrated constant part of the
//         link before it (DH or Hayati), axis z, limits home +- the actuator range; metres
//         and radians as URDF wants.
//   csv   parallel mechanisms: one row per leg with the base and platform joint coordinates,
//         the leg offset and the leg at home (the convention in a comment header); serial
//         arms: one row per joint with its calibrated DH/Hayati parameters.
//   json  any mechanism: the same content as plain JSON (docs/exporting.md).
//   camera-info
//         a model with one camera: its intrinsics and distortion as ROS's camera_info YAML
//         (OpenCV's camera matrix and plumb_bob k1, k2, p1, p2, k3), the form ROS camera
//         drivers and image_proc load.
// Each throws ExportError with one sentence when the mechanism cannot take the format.

#include <stdexcept>
#include <string>

#include "kincal/framework/kinematics/measurement_model.hpp"

namespace kincal {

class ExportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Where the model came from, written into every export.
struct ExportSource {
  std::string model_file;
  std::string sha256;  ///< of the model file's bytes
};

std::string export_urdf(const MeasurementModel& model, const ExportSource& source);
std::string export_csv(const MeasurementModel& model, const ExportSource& source);
std::string export_json(const MeasurementModel& model, const ExportSource& source);

std::string export_camera_info(const MeasurementModel& model, const ExportSource& source);
/// The model in `format`: urdf, csv, json, camera-info, or one a plug-in registered for its
/// mechanism type (ModelRegistry::export_format). Throws std::invalid_argument naming the formats
/// there are for an unknown one ("format 'x': expected urdf, csv, json for mechanism 'hexapod'"),
/// ExportError when the mechanism cannot take the format, and nlohmann::json::exception when a
/// value cannot be written as JSON.
std::string export_model(const MeasurementModel& model, const std::string& format,
                         const ExportSource& source);

}  // namespace kincal
