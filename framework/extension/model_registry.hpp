#pragma once
// Mechanism types, sensor types and preset models by name, beside the SolverRegistry.
// Everything that reads, writes or names models dispatches through it: model files
// (models/model_io.hpp), `kincal model --preset`, `kincal list models|sensors`, and the
// conformance tests, which hold every registered preset, mechanism and sensor to the same
// checks. Registration is explicit (register_builtin_models() in models/builtin_models.cpp:
// one line per type); a program may add its own types and presets to the global registry
// before using it.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "kincal/framework/io/json_fields.hpp"
#include "kincal/framework/kinematics/measurement_model.hpp"

namespace kincal {

/// A mechanism type: how model files describe it.
struct MechanismType {
  std::string type;         ///< as in model files' "mechanism": {"type": ...}, e.g. "serial-arm"
  std::string description;  ///< one line
  /// Builds a mechanism from its JSON object (as in the file, "type" included); fails
  /// through `where` (JsonPath::fail) on bad input.
  std::function<std::shared_ptr<const Mechanism>(const Json& object, const JsonPath& where)> read;
  /// The JSON object of `mechanism` (without "type") with parameter values `values` (its
  /// own slice, in parameters() order), such that read() gives them back as nominal values.
  std::function<Json(const Mechanism& mechanism, const Eigen::Ref<const VectorXd>& values)> write;
};

/// A sensor type: how model files describe it.
struct SensorType {
  std::string type;         ///< e.g. "length-gauge"
  std::string description;  ///< one line
  std::function<std::shared_ptr<const Sensor>(const Json& object, const JsonPath& where)> read;
  /// Without "type"; "name" included.
  std::function<Json(const Sensor& sensor, const Eigen::Ref<const VectorXd>& values)> write;
};

/// A parameter-only constraint type (framework/kinematics/parameter_constraint.hpp): how model
/// files describe it, in their top-level "constraints" array.
struct ConstraintType {
  std::string type;         ///< e.g. "fixture-distance"
  std::string description;  ///< one line
  /// Builds a constraint on `model` (its mechanism and sensors, read first) from its JSON
  /// object ("type" included); fails through `where` on bad input.
  std::function<std::shared_ptr<const ParameterConstraint>(
      const Json& object, const JsonPath& where, const MeasurementModel& model)>
      read;
  /// Its JSON object, without "type".
  std::function<Json(const ParameterConstraint& constraint)> write;
};

/// A ready-made model: a mechanism with sensors, nominal values and a default free mask
/// that the data of a default simulation can determine.
struct ModelPreset {
  std::string name;         ///< e.g. "puma560"
  std::string description;  ///< one line, citing where the nominal values come from
  std::function<std::shared_ptr<MeasurementModel>()> make;
};

/// Where an exported model came from, written into the export.
struct ExportOrigin {
  std::string model_file;
  std::string sha256;  ///< of the model file's bytes
};

/// A further `kincal export --format` for one mechanism type (urdf, csv and json are
/// kincal's own; json works for every mechanism). The model's nominal values are the ones
/// to export (a calibrated model file's).
struct ExportFormat {
  std::string format;          ///< as given to --format, e.g. "five-bar-csv"
  std::string mechanism_type;  ///< the mechanism type it writes
  std::string description;     ///< one line
  /// The whole text of the export; throws std::invalid_argument with one sentence when the
  /// model cannot be written so.
  std::function<std::string(const MeasurementModel& model, const ExportOrigin& origin)> write;
};

class ModelRegistry {
 public:
  /// The process-wide registry with the built-in types and presets registered.
  static ModelRegistry& global();

  /// Each throws std::logic_error when the name is already taken or a function is missing.
  void add_mechanism(MechanismType type);
  void add_sensor(SensorType type);
  void add_preset(ModelPreset preset);
  /// Throws std::logic_error when the mechanism type already has that format, when the
  /// format is one of kincal's own (urdf, csv, json) or when `write` is missing.
  void add_export_format(ExportFormat format);
  void add_constraint(ConstraintType type);

  /// Throw std::invalid_argument listing the registered names when `name` is unknown.
  const MechanismType& mechanism(const std::string& type) const;
  const SensorType& sensor(const std::string& type) const;
  const ModelPreset& preset(const std::string& name) const;
  /// A fresh model of the preset `name`.
  std::shared_ptr<MeasurementModel> make_preset(const std::string& name) const;

  const std::vector<MechanismType>& mechanisms() const { return mechanisms_; }
  const std::vector<SensorType>& sensors() const { return sensors_; }
  const std::vector<ModelPreset>& presets() const { return presets_; }
  const std::vector<ExportFormat>& export_formats() const { return export_formats_; }
  /// Throws std::invalid_argument listing the registered names when `type` is unknown.
  const ConstraintType& constraint(const std::string& type) const;
  const std::vector<ConstraintType>& constraints() const { return constraints_; }
  /// The registered format `format` of `mechanism_type`, or nullptr.
  const ExportFormat* export_format(const std::string& mechanism_type,
                                    const std::string& format) const;

 private:
  std::vector<MechanismType> mechanisms_;
  std::vector<SensorType> sensors_;
  std::vector<ModelPreset> presets_;
  std::vector<ExportFormat> export_formats_;
  std::vector<ConstraintType> constraints_;
};

/// Defined in models/builtin_models.cpp: registers every mechanism type, sensor type and
/// preset kincal ships.
void register_builtin_models(ModelRegistry& registry);

}  // namespace kincal
