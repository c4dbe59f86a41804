#pragma once
// Mechanisms written in Python (prototypes): a kincal.mechanisms.Mechanism subclass gives the
// pose its actuator values reach and the pose's two Jacobians in numpy (an open chain: forward
// kinematics is explicit); PythonMechanism makes it a C++ Mechanism, so that simulation,
// calibration, every backend and kincal's conformance checks use it as a built-in one (slow
// path: each evaluation takes the GIL). A Python error cannot cross the solvers: the first is
// kept, forward kinematics reports a non-finite pose, and rethrow() raises it afterwards.

#include <exception>
#include <mutex>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "kincal/framework/kinematics/mechanism.hpp"

namespace kincal::python {

class PythonMechanism : public Mechanism {
 public:
  explicit PythonMechanism(py::object impl);
  ~PythonMechanism() override;

  std::string type() const override { return type_; }
  const std::vector<Actuator>& actuators() const override { return actuators_; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  const Pose& home_pose() const override { return home_; }

  InverseKinematicsResult home_actuators(const ParamsRef& params,
                                         Eigen::Ref<VectorXd> q) const override;
  /// A Python mechanism states no inverse kinematics: unreachable, with that reason.
  InverseKinematicsResult inverse_kinematics(const ParamsRef& params, const Pose& pose,
                                             Eigen::Ref<VectorXd> q) const override;
  ForwardKinematicsResult forward_kinematics(
      const ParamsRef& params, const ActuatorsRef& q, const Pose& start,
      const ForwardKinematicsOptions& options) const override;
  void pose_jacobian_params(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
                            Eigen::Ref<Matrix6Xd> J_pose_params) const override;
  bool pose_jacobian_actuators(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
                               const ForwardKinematicsOptions& options,
                               Eigen::Ref<Matrix6Xd> J_pose_actuators) const override;

  /// Raises the first Python error kept since the last call, if any.
  void rethrow() const;

 private:
  struct Evaluation {
    bool ok = false;
    Pose pose;
    Matrix6Xd J_params, J_actuators;
  };
  Evaluation evaluate(const ParamsRef& params, const ActuatorsRef& q, bool jacobians) const;
  void remember(std::exception_ptr e) const;

  py::object impl_;
  std::string type_;
  std::vector<Actuator> actuators_;
  std::vector<Parameter> parameters_;
  VectorXd home_actuators_;
  Pose home_;
  mutable std::mutex mutex_;
  mutable std::exception_ptr error_;
};

/// Raises the first Python error any Python mechanism or sensor of `model` kept.
void rethrow_python_errors(const MeasurementModel& model);

}  // namespace kincal::python
