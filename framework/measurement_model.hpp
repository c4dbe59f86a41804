#pragma once
// A mechanism and its sensors over one combined parameter vector
//   [mechanism parameters | sensor 1 parameters | sensor 2 ...]
// Given actuator values, it predicts every sensor's readings and, by the chain rule,
//   J_readings_params = J_reading_pose * J_pose_params  (+ J_reading_params on the sensor block).

#include <memory>
#include <vector>

#include "kincal/framework/mechanism.hpp"
#include "kincal/framework/sensor.hpp"

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

  /// Predicted readings for actuator values q (forward kinematics from the home pose) and,
  /// when J is non-null, their Jacobian (num_readings x num_parameters, presized) with
  /// respect to the full parameter vector. Returns the forward kinematics result: when it
  /// failed, the readings are left unspecified.
  ForwardKinematicsResult predict(const Eigen::Ref<const VectorXd>& params, const ActuatorsRef& q,
                                  Eigen::Ref<VectorXd> readings, Eigen::Ref<MatrixXd>* J,
                                  Workspace& ws) const;

  /// Readings at a known pose (no forward kinematics): used to simulate sensors.
  void predict_at_pose(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                       Eigen::Ref<VectorXd> readings) const;

  /// Offsets of the sensor parameter blocks in the combined vector.
  int sensor_parameter_offset(int sensor_index) const { return sensor_offsets_[sensor_index]; }

 private:
  std::shared_ptr<const Mechanism> mechanism_;
  std::vector<std::shared_ptr<const Sensor>> sensors_;
  ParameterSet parameters_;
  std::vector<int> sensor_offsets_;
  int num_readings_ = 0;
  ForwardKinematicsOptions fk_options_;
};

}  // namespace kincal
