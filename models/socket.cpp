#include "kincal/models/socket.hpp"

#include "kincal/framework/kinematics/units.hpp"

namespace kincal {

Socket::Socket(std::string name, const Vector3d& point) : name_(std::move(name)) {
  const char* axes[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k)
    parameters_.push_back({name_ + ".point." + axes[k], point[k], kMillimetre, false});
}

std::vector<std::string> Socket::reading_names() const {
  return {name_ + ".x", name_ + ".y", name_ + ".z"};
}

std::vector<std::string> Socket::reading_units() const {
  return {kMillimetre, kMillimetre, kMillimetre};
}

void Socket::predict(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                     Eigen::Ref<VectorXd> reading, MatrixXd* J_reading_pose,
                     MatrixXd* J_reading_params) const {
  reading = pose.translation - params.segment<3>(kPointIndex);
  if (J_reading_pose) {
    // The tool point is the pose's origin: a rotation about it does not move it.
    J_reading_pose->leftCols<3>().setIdentity();
    J_reading_pose->rightCols<3>().setZero();
  }
  if (J_reading_params) J_reading_params->middleCols<3>(kPointIndex) = -Matrix3d::Identity();
}

}  // namespace kincal
