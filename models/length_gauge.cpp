#include "kincal/models/length_gauge.hpp"

namespace kincal {

LengthGauge::LengthGauge(std::string name, const Vector3d& base_point,
                         const Vector3d& platform_point, double offset)
    : name_(std::move(name)) {
  const char* axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a)
    parameters_.push_back({name_ + ".base." + axes[a], base_point[a], "mm", false});
  for (int a = 0; a < 3; ++a)
    parameters_.push_back({name_ + ".platform." + axes[a], platform_point[a], "mm", false});
  parameters_.push_back({name_ + ".offset", offset, "mm", false});
}

void LengthGauge::predict(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                          Eigen::Ref<VectorXd> reading, MatrixXd* J_reading_pose,
                          MatrixXd* J_reading_params) const {
  const Vector3d a = pose.rotation * params.segment<3>(kPlatformIndex);
  const Vector3d v = pose.translation + a - params.segment<3>(kBaseIndex);
  const double length = v.norm();
  reading[0] = length + params[kOffsetIndex];
  if (!J_reading_pose && !J_reading_params) return;
  const Vector3d n = v / length;
  if (J_reading_pose) {
    J_reading_pose->block<1, 3>(0, 0) = n.transpose();
    J_reading_pose->block<1, 3>(0, 3) = a.cross(n).transpose();
  }
  if (J_reading_params) {
    J_reading_params->block<1, 3>(0, kBaseIndex) = -n.transpose();
    J_reading_params->block<1, 3>(0, kPlatformIndex) = n.transpose() * pose.rotation;
    (*J_reading_params)(0, kOffsetIndex) = 1.0;
  }
}

}  // namespace kincal
