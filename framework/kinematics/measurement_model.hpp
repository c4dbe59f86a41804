#pragma once
// A mechanism and its sensors over one combined parameter vector
//   [mechanism parameters | sensor 1 parameters | sensor 2 ...]
// Given actuator values, it predicts every sensor's readings and, by the chain rule,
//   J_readings_params = J_reading_pose * J_pose_params  (+ J_reading_params on the sensor block).
// A measured reading may be missing (NaN: the sensor did not see that configuration); it then
// contributes no residual.

#include <memory>
#include <vector>

#include "kincal/framework/kinematics/mechanism.hpp"
#include "kincal/framework/kinematics/parameter_constraint.hpp"
#include "kincal/framework/kinematics/sensor.hpp"

namespace kincal {

class MeasurementModel {
 public:
  MeasurementModel(std::shared_ptr<const Mechanism> mechanism,
                   std::vector<std::shared_ptr<const Sensor>> sensors);

  const Mechanism& mechanism() const { return *mechanism_; }
  std::shared_ptr<const Mechanism> mechanism_ptr() const { return mechanism_; }
  const std::vector<std::shared_ptr<const Sensor>>& sensors() const { return sensors_; }
  /// Combined parameters with nominal values and the default free mask.
  const ParameterSet& parameters() const { return parameters_; }
  /// Editable free/fixed mask and nominal values (layout is fixed by the components).
  ParameterSet& parameters() { return parameters_; }
  int num_parameters() const { return parameters_.size(); }
  /// Scalar readings per configuration, all sensors together.
  int num_readings() const { return num_readings_; }
  std::vector<std::string> reading_names() const;
  std::vector<std::string> reading_units() const;
  /// First reading of sensor `sensor_index` in a configuration's reading vector.
  int sensor_reading_offset(int sensor_index) const { return reading_offsets_[sensor_index]; }

  /// Standard deviation of each reading's noise (its unit), when known: calibration weighs
  /// residuals by 1 / std (whitening) so that readings of different units and accuracy
  /// count by what they are worth. All 1 (unweighted) unless set.
  const VectorXd& reading_std() const { return reading_std_; }
  /// Whether any reading_std differs from 1.
  bool weighted() const { return (reading_std_.array() != 1.0).any(); }
  /// Sets the std of every reading whose name matches the glob `pattern`; throws
  /// std::invalid_argument when none does or the value is not finite and > 0.
  int set_reading_std(const std::string& pattern, double std);

  /// Half-width of the configuration box around home, per actuator (its unit), from which
  /// simulation and experiment design draw: the mechanism's defaults unless changed.
  const VectorXd& actuator_ranges() const { return actuator_ranges_; }
  /// Sets the range of every actuator whose name matches the glob `pattern`; throws
  /// std::invalid_argument when none does or the value is not finite and >= 0.
  int set_actuator_range(const std::string& pattern, double half_width);

  ForwardKinematicsOptions& forward_kinematics_options() { return fk_options_; }
  const ForwardKinematicsOptions& forward_kinematics_options() const { return fk_options_; }

  /// Scratch space for predict(); one per thread, reused across calls.
  struct Workspace {
    MatrixX6d J_readings_pose;  ///< every sensor's J_reading_pose, stacked
    std::vector<MatrixXd> J_reading_pose;
    std::vector<MatrixXd> J_reading_params;
  };
  Workspace make_workspace() const;
  /// Resizes `ws` for this model (no-op when it already fits).
  void prepare(Workspace& ws) const;

  /// Predicted readings for actuator values q (forward kinematics from `start`, or from the
  /// home pose when null, in at most `max_newton_steps` steps when >= 0) and, when J is
  /// non-null, their Jacobian (num_readings x num_parameters, presized) with respect to the
  /// full parameter vector. Returns the forward kinematics result, with the pose reached:
  /// when it failed, the readings are left unspecified. The readings of a sensor that does
  /// not read at the pose reached (Sensor::reads_at) are NaN, their Jacobian rows zero.
  ForwardKinematicsResult predict(const Eigen::Ref<const VectorXd>& params, const ActuatorsRef& q,
                                  Eigen::Ref<VectorXd> readings, Eigen::Ref<MatrixXd>* J,
                                  Workspace& ws, const Pose* start = nullptr,
                                  int max_newton_steps = -1) const;

  /// Readings at a known pose (no forward kinematics): used to simulate sensors. NaN for a
  /// sensor that does not read there, as in predict().
  void predict_at_pose(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                       Eigen::Ref<VectorXd> readings) const;

  /// Readings at a known pose as a simulated measurement takes them: predict_at_pose, and the
  /// readings a sensor would not take there NaN (Sensor::drop_unseen: a camera's points
  /// outside its image). Returns the number of readings left missing (0: every one taken).
  int simulate_at_pose(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                       Eigen::Ref<VectorXd> readings) const;

  /// Residuals of predicted against measured readings of one configuration, sensor by
  /// sensor (Sensor::reading_error; predicted - measured for plain readings). A missing
  /// measured reading (NaN) gives a zero residual. When J is non-null it holds
  /// J_readings_params from predict() on entry and J_residuals_params on return: rows of
  /// missing readings zeroed, rows of manifold readings mapped by J_error_predicted.
  void reading_errors(const Eigen::Ref<const VectorXd>& predicted,
                      const Eigen::Ref<const VectorXd>& measured, Eigen::Ref<VectorXd> errors,
                      Eigen::Ref<MatrixXd>* J) const;
  /// `readings` moved by the tangent perturbation `delta`, sensor by sensor (Sensor::retract).
  void retract(Eigen::Ref<VectorXd> readings, const Eigen::Ref<const VectorXd>& delta) const;

  /// Whether any sensor can fail to read (Sensor::can_miss).
  bool sensors_can_miss() const { return sensors_can_miss_; }
  /// Sensor `sensor_index` reads at `pose` (Sensor::reads_at with its slice of `params`);
  /// when not, the reason in `reason` (non-null).
  bool sensor_reads_at(const Eigen::Ref<const VectorXd>& params, const Pose& pose, int sensor_index,
                       std::string* reason) const;
  /// Index of the sensor that owns reading `reading_index`.
  int sensor_of_reading(int reading_index) const;

  /// The mechanism's identification_priority over the whole parameter vector (empty when the
  /// mechanism states none): its own entries, 0 for the sensors' parameters, and -1 (kept
  /// first) for a sensor that is only a point in the measurement frame (a socket), which has no
  /// frame of its own: the mechanism's base frame then holds the measurement frame.
  std::vector<int> identification_priority() const;

  /// Offsets of the sensor parameter blocks in the combined vector.
  int sensor_parameter_offset(int sensor_index) const { return sensor_offsets_[sensor_index]; }

  /// Residuals on the parameters alone (framework/kinematics/parameter_constraint.hpp), which a
  /// calibration adds once (framework/calibration/constrained_problem.hpp). None unless added.
  const std::vector<std::shared_ptr<const ParameterConstraint>>& constraints() const {
    return constraints_;
  }
  /// Indices of constraint k's parameter_names() in the parameter vector.
  const std::vector<int>& constraint_parameter_indices(int k) const {
    return constraint_indices_[k];
  }
  /// Adds a constraint; throws std::invalid_argument naming a parameter it reads that the
  /// model does not have.
  void add_constraint(std::shared_ptr<const ParameterConstraint> constraint);

 private:
  std::shared_ptr<const Mechanism> mechanism_;
  std::vector<std::shared_ptr<const Sensor>> sensors_;
  ParameterSet parameters_;
  std::vector<int> sensor_offsets_;
  std::vector<int> reading_offsets_;
  int num_readings_ = 0;
  bool has_manifold_readings_ = false;
  bool sensors_can_miss_ = false;
  VectorXd actuator_ranges_;
  VectorXd reading_std_;
  ForwardKinematicsOptions fk_options_;
  std::vector<std::shared_ptr<const ParameterConstraint>> constraints_;
  std::vector<std::vector<int>> constraint_indices_;
};

}  // namespace kincal
