#pragma once
// A point tracker (laser tracker): a target point on the end effector, p (tool/platform
// frame), seen in the tracker's frame F = (R_f, t_f) (base coordinates: x_base = R_f x + t_f):
//   reading = R_f^T (R p + t - t_f)        three readings <name>.x, .y, .z (mm)
// for the mechanism's pose (R, t).
// Parameters: <name>.frame.{x, y, z, rx, ry, rz} (a frame block, pose.hpp),
// <name>.target.{x, y, z}.

#include "kincal/framework/kinematics/sensor.hpp"

namespace kincal {

class ModelRegistry;

class PointTracker final : public Sensor {
 public:
  /// `frame`: the tracker's frame parameters [x, y, z, rx, ry, rz] (mm, rad;
  /// frame_from_parameters). All parameters fixed by default.
  PointTracker(std::string name, const Vector6d& frame, const Vector3d& target);

  std::string type() const override { return "point-tracker"; }
  const std::string& name() const override { return name_; }
  int num_readings() const override { return 3; }
  std::vector<std::string> reading_names() const override;
  std::vector<std::string> reading_units() const override { return {"mm", "mm", "mm"}; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  /// x, y, z: the measured point in the tracker's frame.
  int position_reading_index() const override { return 0; }

  void predict(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
               Eigen::Ref<VectorXd> reading, MatrixXd* J_reading_pose,
               MatrixXd* J_reading_params) const override;

  static constexpr int kFrameIndex = 0;
  static constexpr int kTargetIndex = 6;

 private:
  std::string name_;
  std::vector<Parameter> parameters_;
};

/// Registers the type (model-file reader/writer).
void register_point_tracker(ModelRegistry& registry);

}  // namespace kincal
