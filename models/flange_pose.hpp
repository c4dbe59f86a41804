#pragma once
// A robot known only by the pose of its flange as its controller reports it: the
// configuration is that pose, and the mechanism has no parameters of its own. For data that
// give the flange pose instead of joint angles (most public hand-eye data sets), so that a
// camera's mounts and intrinsics are calibrated with the same sensor as on a modelled arm:
// what is identified is then the sensor's parameters, the robot's reported poses taken as
// exact.
//
// Actuators (measurement columns), six: flange.x, flange.y, flange.z (mm; the position in
// base coordinates) and flange.rotvec_x, flange.rotvec_y, flange.rotvec_z (rad; the rotation
// vector of the flange's orientation in base coordinates, R = exp([w]x)). A file in metres
// names its columns flange.x_m ... (measurement_file.hpp's unit suffixes).
#include "kincal/framework/kinematics/mechanism.hpp"

namespace kincal {

class ModelRegistry;

class FlangePose final : public Mechanism {
 public:
  /// `home`: the pose around which simulation and design draw configurations;
  /// `position_range_mm`, `rotation_range_rad`: the half-widths of that box (> 0).
  FlangePose(const Pose& home, double position_range_mm, double rotation_range_rad);

  std::string type() const override { return "flange-pose"; }
  const std::vector<Actuator>& actuators() const override { return actuators_; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  const Pose& home_pose() const override { return home_; }
  InverseKinematicsResult inverse_kinematics(const ParamsRef& params, const Pose& pose,
                                             Eigen::Ref<VectorXd> q) const override;
  ForwardKinematicsResult forward_kinematics(
      const ParamsRef& params, const ActuatorsRef& q, const Pose& start,
      const ForwardKinematicsOptions& options = {}) const override;
  void pose_jacobian_params(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
                            Eigen::Ref<Matrix6Xd> J_pose_params) const override;
  /// Exact: the position columns move the position one for one; the rotation vector moves
  /// the orientation by the left Jacobian of SO(3) (pose.hpp).
  bool pose_jacobian_actuators(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
                               const ForwardKinematicsOptions& options,
                               Eigen::Ref<Matrix6Xd> J_pose_actuators) const override;

  double position_range() const { return actuators_[0].default_range; }
  double rotation_range() const { return actuators_[3].default_range; }

  /// The configuration (six actuator values) of a flange pose.
  static Vector6d configuration(const Pose& pose);

 private:
  Pose home_;
  std::vector<Actuator> actuators_;
  std::vector<Parameter> parameters_;
};

/// Registers the type (model-file reader/writer).
void register_flange_pose(ModelRegistry& registry);

}  // namespace kincal
