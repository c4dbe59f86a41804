#include "kincal/models/pose_tracker.hpp"

#include "kincal/framework/kinematics/orientation_columns.hpp"

namespace kincal {

PoseTracker::PoseTracker(std::string name, const Vector6d& frame, const Vector6d& marker)
    : name_(std::move(name)) {
  const char* suffixes[6] = {"x", "y", "z", "rx", "ry", "rz"};
  for (int k = 0; k < 6; ++k)
    parameters_.push_back({name_ + ".frame." + suffixes[k], frame[k], k < 3 ? "mm" : "rad", false});
  for (int k = 0; k < 6; ++k)
    parameters_.push_back(
        {name_ + ".marker." + suffixes[k], marker[k], k < 3 ? "mm" : "rad", false});
}

std::vector<std::string> PoseTracker::reading_names() const {
  std::vector<std::string> names = {name_ + ".x", name_ + ".y", name_ + ".z"};
  for (auto& n : rotation_vector_names(name_)) names.push_back(std::move(n));
  return names;
}

std::vector<ReadingColumns> PoseTracker::alternative_columns() const {
  return orientation_alternatives(name_, 3);
}

std::vector<RefusedColumns> PoseTracker::refused_columns() const {
  return {ambiguous_orientation_columns(name_)};
}

void PoseTracker::predict(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                          Eigen::Ref<VectorXd> reading, MatrixXd* J_reading_pose,
                          MatrixXd* J_reading_params) const {
  const FrameBlock tracker_block = frame_block(params.segment<6>(kFrameIndex));
  const FrameBlock marker_block = frame_block(params.segment<6>(kMarkerIndex));
  const Pose& frame = tracker_block.frame;
  const Pose& marker = marker_block.frame;
  const Matrix3d Rt = frame.rotation.transpose();
  const Vector3d a = pose.rotation * marker.translation;  // marker origin from the pose origin
  const Vector3d v = pose.translation + a - frame.translation;
  reading.head<3>() = Rt * v;
  reading.tail<3>() = log_so3(Rt * pose.rotation * marker.rotation);
  if (J_reading_pose) {
    // The marker's origin moves by dt + dw x a; its rotation turns by dw, which the tracker
    // sees as R_f^T dw.
    J_reading_pose->topLeftCorner<3, 3>() = Rt;
    J_reading_pose->topRightCorner<3, 3>() = -Rt * skew(a);
    J_reading_pose->bottomLeftCorner<3, 3>().setZero();
    J_reading_pose->bottomRightCorner<3, 3>() = Rt;
  }
  if (J_reading_params) {
    MatrixXd& J = *J_reading_params;
    // Turning the tracker by w turns what it sees by -w, about its own origin.
    const Matrix3d& W_frame = tracker_block.angular_jacobian;
    J.block<3, 3>(0, kFrameIndex) = -Rt;
    J.block<3, 3>(3, kFrameIndex).setZero();
    J.block<3, 3>(0, kFrameIndex + 3) = Rt * skew(v) * W_frame;
    J.block<3, 3>(3, kFrameIndex + 3) = -Rt * W_frame;
    // The marker's angles turn it about its origin, in the end effector's axes.
    J.block<3, 3>(0, kMarkerIndex) = Rt * pose.rotation;
    J.block<3, 3>(3, kMarkerIndex).setZero();
    J.block<3, 3>(0, kMarkerIndex + 3).setZero();
    J.block<3, 3>(3, kMarkerIndex + 3) = Rt * pose.rotation * marker_block.angular_jacobian;
  }
}

void PoseTracker::reading_error(const Eigen::Ref<const VectorXd>& predicted,
                                const Eigen::Ref<const VectorXd>& measured,
                                Eigen::Ref<VectorXd> error, MatrixXd* J_error_predicted) const {
  error.head<3>() = predicted.head<3>() - measured.head<3>();
  const Vector3d rotation_error =
      log_so3(exp_so3(predicted.tail<3>()) * exp_so3(measured.tail<3>()).transpose());
  error.tail<3>() = rotation_error;
  if (J_error_predicted) {
    // log(exp(d) R_pred R_meas^T) = e + J_l^-1(e) d to first order.
    J_error_predicted->setIdentity();
    J_error_predicted->bottomRightCorner<3, 3>() = left_jacobian_inverse_so3(rotation_error);
  }
}

void PoseTracker::retract(Eigen::Ref<VectorXd> reading,
                          const Eigen::Ref<const VectorXd>& delta) const {
  reading.head<3>() += delta.head<3>();
  reading.tail<3>() = log_so3(exp_so3(delta.tail<3>()) * exp_so3(reading.tail<3>()));
}

}  // namespace kincal
