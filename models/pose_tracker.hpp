#pragma once
// A pose tracker (optical tracker, camera): a marker frame M = (R_m, t_m) on the end effector
// (tool/platform frame), seen in the tracker's frame F = (R_f, t_f) (base coordinates). For the
// mechanism's pose (R, t) the marker in tracker coordinates is
//   R_y = R_f^T R R_m,   t_y = R_f^T (R t_m + t - t_f)
// and the six readings are <name>.x, .y, .z = t_y (mm) and <name>.rotvec_x, _y, _z = log(R_y),
// its rotation vector (axis times angle, rad). A measurement file may give the orientation
// as roll-pitch-yaw or a quaternion instead (orientation_columns.hpp); <name>.rx, .ry, .rz
// are refused: they do not say which convention they hold.
//
// The rotation readings live on SO(3): the residual of a predicted against a measured
// reading is [t_pred - t_meas; log(R_pred R_meas^T)] (the rotation error in tracker axes,
// continuous where the rotation vector itself flips at pi), and the Jacobian rows of the
// rotation are derivatives in its tangent space: R_y <- exp(d) R_y.
// Parameters: <name>.frame.{x, y, z, rx, ry, rz}, <name>.marker.{x, y, z, rx, ry, rz}.

#include "kincal/framework/kinematics/sensor.hpp"

namespace kincal {

class ModelRegistry;

class PoseTracker final : public Sensor {
 public:
  /// `frame` and `marker`: frame parameters [x, y, z, rx, ry, rz] (mm, rad;
  /// frame_from_parameters) of the tracker (base coordinates) and of the marker (end-effector
  /// coordinates). All parameters fixed by default.
  PoseTracker(std::string name, const Vector6d& frame, const Vector6d& marker);

  std::string type() const override { return "pose-tracker"; }
  const std::string& name() const override { return name_; }
  int num_readings() const override { return 6; }
  std::vector<std::string> reading_names() const override;
  std::vector<ReadingColumns> alternative_columns() const override;
  std::vector<RefusedColumns> refused_columns() const override;
  std::vector<std::string> reading_units() const override {
    return {"mm", "mm", "mm", "rad", "rad", "rad"};
  }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  /// x, y, z: the measured point in the tracker's frame.
  int position_reading_index() const override { return 0; }
  /// rotvec_x, _y, _z: the marker's orientation in the tracker's frame.
  int orientation_reading_index() const override { return 3; }

  void predict(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
               Eigen::Ref<VectorXd> reading, MatrixXd* J_reading_pose,
               MatrixXd* J_reading_params) const override;

  bool has_manifold_readings() const override { return true; }
  /// [t_pred - t_meas; log(R_pred R_meas^T)], J_error_predicted = diag(I, J_l^-1(rotation
  /// error)) (pose.hpp: left_jacobian_inverse_so3).
  void reading_error(const Eigen::Ref<const VectorXd>& predicted,
                     const Eigen::Ref<const VectorXd>& measured, Eigen::Ref<VectorXd> error,
                     MatrixXd* J_error_predicted) const override;
  /// t += d_t, R <- exp(d_r) R.
  void retract(Eigen::Ref<VectorXd> reading,
               const Eigen::Ref<const VectorXd>& delta) const override;

  static constexpr int kFrameIndex = 0;
  static constexpr int kMarkerIndex = 6;

 private:
  std::string name_;
  std::vector<Parameter> parameters_;
};

/// Registers the type (model-file reader/writer).
void register_pose_tracker(ModelRegistry& registry);

}  // namespace kincal
