#pragma once
// A planar two-link arm: the smallest mechanism written outside kincal, for
// docs/extending.md. Two revolute joints about z; link lengths and joint zero offsets are
// its parameters:
//   link1.length, link2.length (mm), joint1.offset, joint2.offset (rad).
// The end effector frame sits at the tip of link 2, its x axis along the link.

#include <kincal/framework/kinematics/mechanism.hpp>

namespace example {

class TwoLinkArm final : public kincal::Mechanism {
 public:
  /// Nominal link lengths (mm); offsets nominally 0. Home: joints at (0.5, 1.0) rad.
  TwoLinkArm(double link1, double link2);

  std::string type() const override { return "two-link-arm"; }
  const std::vector<kincal::Actuator>& actuators() const override { return actuators_; }
  const std::vector<kincal::Parameter>& parameters() const override { return parameters_; }
  const kincal::Pose& home_pose() const override { return home_; }
  kincal::InverseKinematicsResult home_actuators(const kincal::ParamsRef& params,
                                                 Eigen::Ref<kincal::VectorXd> q) const override;

  kincal::InverseKinematicsResult inverse_kinematics(const kincal::ParamsRef& params,
                                                     const kincal::Pose& pose,
                                                     Eigen::Ref<kincal::VectorXd> q) const override;
  kincal::ForwardKinematicsResult forward_kinematics(
      const kincal::ParamsRef& params, const kincal::ActuatorsRef& q, const kincal::Pose& start,
      const kincal::ForwardKinematicsOptions& options = {}) const override;
  void pose_jacobian_params(const kincal::ParamsRef& params, const kincal::ActuatorsRef& q,
                            const kincal::Pose& pose,
                            Eigen::Ref<kincal::Matrix6Xd> J_pose_params) const override;

  static constexpr double kHome[2] = {0.5, 1.0};

 private:
  std::vector<kincal::Actuator> actuators_;
  std::vector<kincal::Parameter> parameters_;
  kincal::Pose home_;
};

}  // namespace example
