#pragma once
// The compare workflow: a model (a calibration's result) against a known truth (a
// simulation's truth file): the error of each parameter, and the error of the mechanism's
// pose over a set of configurations. What `kincal compare` does between reading its files and
// writing its outputs. Closes the design loop: design -> simulate -> calibrate -> compare.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "kincal/framework/kinematics/measurement_model.hpp"

namespace kincal {

struct CompareRequest {
  std::shared_ptr<const MeasurementModel> truth, model;  ///< at their nominal values
  /// Where to compare the poses: given (a file's actuator columns), or, when empty,
  /// `workspace_poses` configurations drawn in the truth's actuator box from `seed`.
  MatrixXd configurations;
  std::string data_file;  ///< names `configurations` when given
  int workspace_poses = 200;
  std::uint64_t seed = 1;
  /// Names of the inputs, in the report.
  std::string truth_file, model_file;
};

struct ParameterError {
  std::string name, unit;
  double truth = 0, estimate = 0, error = 0;  ///< error = estimate - truth (angles wrapped)
  bool free = false;
};

struct UnitParameterError {
  int count = 0;
  double rms = 0, max_abs = 0;
  std::string max_abs_parameter;
};

struct PoseErrors {
  std::vector<double> position, orientation;  ///< per configuration; NaN where unreachable
  int fk_failures = 0;
  double position_mean = 0, position_rms = 0, position_max = 0;
  double orientation_mean = 0, orientation_rms = 0, orientation_max = 0;
};

struct CompareResult {
  /// The parameters free in the model and those whose values differ from the truth's.
  std::vector<ParameterError> parameters;
  std::map<std::string, UnitParameterError> by_unit;
  PoseErrors pose;
  int configurations = 0;
  std::string where;  ///< the configurations in words
  bool from_data = false;
  /// The request's names and seed, for the renderings.
  std::string truth_file, model_file, data_file;
  std::uint64_t seed = 1;
};

/// Runs the comparison. Throws std::invalid_argument when the two models do not have the
/// same parameters, actuators and readings, the truth's workspace cannot be sampled, forward
/// kinematics fails at every configuration, or the errors are not finite.
CompareResult compare_models(const CompareRequest& request);

/// The program's text and JSON renderings (`kincal compare`).
std::string comparison_text(const CompareResult& result);
nlohmann::ordered_json comparison_json(const CompareResult& result);

}  // namespace kincal
