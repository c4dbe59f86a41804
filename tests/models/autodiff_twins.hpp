#pragma once
// Automatic-derivative twins of three built-in types, for tests and benchmarks only: the
// same parameters, actuators and kinematics as the hand-written type (everything but the
// derivatives is delegated to it), with every Jacobian taken by framework/kinematics/autodiff.hpp
// from one function template. Their Jacobians must equal the hand-written ones (to rounding) and
// finite differences (tests/models/autodiff_test.cpp); benchmarks/micro_benchmarks.cpp
// measures what the automatic derivatives cost.

#include <memory>

#include "kincal/framework/kinematics/autodiff.hpp"
#include "kincal/framework/kinematics/measurement_model.hpp"
#include "kincal/models/hexapod.hpp"
#include "kincal/models/length_gauge.hpp"
#include "kincal/models/serial_arm.hpp"

namespace kincal::testing {

/// reading = |R a_p + t - a_b| + offset (LengthGauge).
class AutoDiffLengthGauge final : public AutoDiffSensor<AutoDiffLengthGauge, 7, 1> {
 public:
  explicit AutoDiffLengthGauge(const LengthGauge& hand) : hand_(hand) {}
  std::string type() const override { return "length-gauge-autodiff"; }
  const std::string& name() const override { return hand_.name(); }
  std::vector<std::string> reading_units() const override { return hand_.reading_units(); }
  const std::vector<Parameter>& parameters() const override { return hand_.parameters(); }

  template <class T>
  void autodiff_readings(const T* params, const PoseT<T>& pose, T* readings) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> base(params), platform(params + 3);
    readings[0] = (pose.transform_point(platform) - base).norm() + params[6];
  }

 private:
  LengthGauge hand_;
};

/// g_i = |t + R p_i - b_i| - (q_i + o_i) (Hexapod).
class AutoDiffHexapod final : public AutoDiffClosedChain<AutoDiffHexapod, 6> {
 public:
  explicit AutoDiffHexapod(const Hexapod& hand) : hand_(hand) {}
  std::string type() const override { return "hexapod-6ups-autodiff"; }
  const std::vector<Actuator>& actuators() const override { return hand_.actuators(); }
  const std::vector<Parameter>& parameters() const override { return hand_.parameters(); }
  const Pose& home_pose() const override { return hand_.home_pose(); }
  InverseKinematicsResult inverse_kinematics(const ParamsRef& params, const Pose& pose,
                                             Eigen::Ref<VectorXd> q) const override {
    return hand_.inverse_kinematics(params, pose, q);
  }
  bool actuators_valid(const ParamsRef& params, const ActuatorsRef& q) const override {
    return hand_.actuators_valid(params, q);
  }

  template <class T>
  void autodiff_constraints(const T* params, const ActuatorsRef& q, const PoseT<T>& pose,
                            T* g) const {
    for (int leg = 0; leg < Hexapod::kLegs; ++leg) {
      const T* p = params + Hexapod::base_index(leg);
      const Eigen::Map<const Eigen::Matrix<T, 3, 1>> base(p), platform(p + 3);
      g[leg] = (pose.transform_point(platform) - base).norm() - (q[leg] + p[6]);
    }
  }

 private:
  Hexapod hand_;
};

/// A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i) (DH) or Rz(theta_i) Tx(a_i) Rx(alpha_i)
/// Ry(beta_i) (Hayati), the joint value added to theta or d (SerialArm).
class AutoDiffSerialArm final : public AutoDiffSerialChain<AutoDiffSerialArm, 4> {
 public:
  explicit AutoDiffSerialArm(const SerialArm& hand) : hand_(hand) {}
  std::string type() const override { return "serial-arm-autodiff"; }
  const std::vector<Actuator>& actuators() const override { return hand_.actuators(); }
  const std::vector<Parameter>& parameters() const override { return hand_.parameters(); }
  const Pose& home_pose() const override { return hand_.home_pose(); }
  InverseKinematicsResult home_actuators(const ParamsRef& params,
                                         Eigen::Ref<VectorXd> q) const override {
    return hand_.home_actuators(params, q);
  }
  InverseKinematicsResult inverse_kinematics(const ParamsRef& params, const Pose& pose,
                                             Eigen::Ref<VectorXd> q) const override {
    return hand_.inverse_kinematics(params, pose, q);
  }
  int num_joints() const { return hand_.num_joints(); }

  template <class T>
  PoseT<T> autodiff_link(int joint, const T* link, const T& q) const {
    const SerialJoint& j = hand_.nominal_geometry().joints[joint];
    const bool revolute = j.type == JointType::kRevolute;
    const T zero(0.0);
    const T theta = revolute ? T(link[SerialArm::kTheta] + q) : link[SerialArm::kTheta];
    if (j.convention == LinkConvention::kDh) {
      const T d = revolute ? link[SerialArm::kDOrBeta] : T(link[SerialArm::kDOrBeta] + q);
      return ad::rot_z(theta) * ad::translation(link[SerialArm::kA], zero, d) *
             ad::rot_x(link[SerialArm::kAlpha]);
    }
    return ad::rot_z(theta) * ad::translation(link[SerialArm::kA], zero, zero) *
           ad::rot_x(link[SerialArm::kAlpha]) * ad::rot_y(link[SerialArm::kDOrBeta]);
  }

 private:
  SerialArm hand_;
};

/// The model with its mechanism and length gauges replaced by their twins (other sensors
/// kept), the same free mask.
inline std::shared_ptr<MeasurementModel> autodiff_twin(const MeasurementModel& model) {
  std::shared_ptr<const Mechanism> mechanism = model.mechanism_ptr();
  if (auto hexapod = std::dynamic_pointer_cast<const Hexapod>(mechanism))
    mechanism = std::make_shared<AutoDiffHexapod>(*hexapod);
  else if (auto arm = std::dynamic_pointer_cast<const SerialArm>(mechanism))
    mechanism = std::make_shared<AutoDiffSerialArm>(*arm);
  std::vector<std::shared_ptr<const Sensor>> sensors;
  for (const auto& sensor : model.sensors()) {
    if (auto gauge = std::dynamic_pointer_cast<const LengthGauge>(sensor))
      sensors.push_back(std::make_shared<AutoDiffLengthGauge>(*gauge));
    else
      sensors.push_back(sensor);
  }
  auto twin = std::make_shared<MeasurementModel>(mechanism, sensors);
  for (int i = 0; i < model.num_parameters(); ++i)
    twin->parameters().set_free(model.parameters()[i].name, model.parameters()[i].free);
  return twin;
}

}  // namespace kincal::testing
