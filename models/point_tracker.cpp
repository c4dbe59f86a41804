#include "kincal/models/point_tracker.hpp"

namespace kincal {

PointTracker::PointTracker(std::string name, const Vector6d& frame, const Vector3d& target)
    : name_(std::move(name)) {
  const char* suffixes[6] = {"x", "y", "z", "rx", "ry", "rz"};
  for (int k = 0; k < 6; ++k)
    parameters_.push_back({name_ + ".frame." + suffixes[k], frame[k], k < 3 ? "mm" : "rad", false});
  for (int k = 0; k < 3; ++k)
    parameters_.push_back({name_ + ".target." + suffixes[k], target[k], "mm", false});
}

std::vector<std::string> PointTracker::reading_names() const {
  return {name_ + ".x", name_ + ".y", name_ + ".z"};
}

void PointTracker::predict(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                           Eigen::Ref<VectorXd> reading, MatrixXd* J_reading_pose,
                           MatrixXd* J_reading_params) const {
  const FrameBlock tracker_block = frame_block(params.segment<6>(kFrameIndex));
  const Pose& frame = tracker_block.frame;
  const Matrix3d Rt = frame.rotation.transpose();
  const Vector3d a = pose.rotation * params.segment<3>(kTargetIndex);
  const Vector3d v = pose.translation + a - frame.translation;  // target from the tracker
  reading = Rt * v;
  if (J_reading_pose) {
    // The target moves by dt + dw x a.
    J_reading_pose->leftCols<3>() = Rt;
    J_reading_pose->rightCols<3>() = -Rt * skew(a);
  }
  if (J_reading_params) {
    // Turning the tracker by w (left, base axes) turns what it sees by -w: d reading =
    // R_f^T (v x w).
    J_reading_params->middleCols<3>(kFrameIndex) = -Rt;
    J_reading_params->middleCols<3>(kFrameIndex + 3) =
        Rt * skew(v) * tracker_block.angular_jacobian;
    J_reading_params->middleCols<3>(kTargetIndex) = Rt * pose.rotation;
  }
}

}  // namespace kincal
