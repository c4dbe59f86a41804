#pragma once
// A length gauge (draw-wire encoder, ball-bar, ...) between a point a_b on the base (base
// frame) and a point a_p on the platform (platform frame):
//   reading = |R a_p + t - a_b| + offset
// Parameters: <name>.base.{x,y,z}, <name>.platform.{x,y,z}, <name>.offset.

#include "kincal/framework/kinematics/sensor.hpp"

namespace kincal {

class ModelRegistry;

class LengthGauge final : public Sensor {
 public:
  /// All parameters fixed by default.
  LengthGauge(std::string name, const Vector3d& base_point, const Vector3d& platform_point,
              double offset = 0.0);

  std::string type() const override { return "length-gauge"; }
  const std::string& name() const override { return name_; }
  int num_readings() const override { return 1; }
  std::vector<std::string> reading_units() const override { return {"mm"}; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }

  void predict(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
               Eigen::Ref<VectorXd> reading, MatrixXd* J_reading_pose,
               MatrixXd* J_reading_params) const override;

  static constexpr int kBaseIndex = 0;
  static constexpr int kPlatformIndex = 3;
  static constexpr int kOffsetIndex = 6;

 private:
  std::string name_;
  std::vector<Parameter> parameters_;
};

/// Registers the type (model-file reader/writer) and its presets.
void register_length_gauge(ModelRegistry& registry);

}  // namespace kincal
