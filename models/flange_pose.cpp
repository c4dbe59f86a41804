#include "kincal/models/flange_pose.hpp"

#include <cmath>
#include <stdexcept>

namespace kincal {

FlangePose::FlangePose(const Pose& home, double position_range_mm, double rotation_range_rad)
    : home_(home) {
  if (!(std::isfinite(position_range_mm) && position_range_mm > 0 &&
        std::isfinite(rotation_range_rad) && rotation_range_rad > 0))
    throw std::invalid_argument("flange-pose: the ranges must be finite and positive");
  if (!home.rotation.allFinite() || !home.translation.allFinite())
    throw std::invalid_argument("flange-pose: the home pose is not finite");
  for (const char* axis : {"x", "y", "z"})
    actuators_.push_back({std::string("flange.") + axis, "mm", position_range_mm});
  for (const char* axis : {"x", "y", "z"})
    actuators_.push_back({std::string("flange.rotvec_") + axis, "rad", rotation_range_rad});
}

Vector6d FlangePose::configuration(const Pose& pose) {
  Vector6d q;
  q << pose.translation, log_so3(pose.rotation);
  return q;
}

InverseKinematicsResult FlangePose::inverse_kinematics(const ParamsRef&, const Pose& pose,
                                                       Eigen::Ref<VectorXd> q) const {
  InverseKinematicsResult result;
  if (!pose.rotation.allFinite() || !pose.translation.allFinite()) {
    result.status = InverseKinematicsStatus::kNonFinite;
    result.reason = "the pose is not finite";
    return result;
  }
  q = configuration(pose);
  return result;
}

ForwardKinematicsResult FlangePose::forward_kinematics(const ParamsRef&, const ActuatorsRef& q,
                                                       const Pose&,
                                                       const ForwardKinematicsOptions&) const {
  ForwardKinematicsResult result;
  if (!q.allFinite()) {
    result.status = ForwardKinematicsStatus::kNonFinite;
    return result;
  }
  result.pose.translation = q.head<3>();
  result.pose.rotation = exp_so3(q.tail<3>());
  return result;
}

void FlangePose::pose_jacobian_params(const ParamsRef&, const ActuatorsRef&, const Pose&,
                                      Eigen::Ref<Matrix6Xd>) const {}

bool FlangePose::pose_jacobian_actuators(const ParamsRef&, const ActuatorsRef& q, const Pose&,
                                         const ForwardKinematicsOptions&,
                                         Eigen::Ref<Matrix6Xd> J_pose_actuators) const {
  if (!q.allFinite()) return false;
  J_pose_actuators.setZero();
  J_pose_actuators.topLeftCorner<3, 3>().setIdentity();
  J_pose_actuators.bottomRightCorner<3, 3>() = left_jacobian_so3(q.tail<3>());
  return true;
}

}  // namespace kincal
