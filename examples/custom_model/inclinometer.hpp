#pragma once
// An inclinometer on the end effector: it reads the angle of the end effector's x axis in
// the base's xy plane, plus a zero offset (`<name>.offset`, rad). One reading in rad, an
// angle: its residual is wrapped to (-pi, pi], the smallest manifold-reading example.

#include <kincal/framework/kinematics/sensor.hpp>

namespace example {

class Inclinometer final : public kincal::Sensor {
 public:
  explicit Inclinometer(std::string name, double offset = 0);

  std::string type() const override { return "inclinometer"; }
  const std::string& name() const override { return name_; }
  int num_readings() const override { return 1; }
  std::vector<std::string> reading_units() const override { return {kincal::kRadian}; }
  const std::vector<kincal::Parameter>& parameters() const override { return parameters_; }

  void predict(const Eigen::Ref<const kincal::VectorXd>& params, const kincal::Pose& pose,
               Eigen::Ref<kincal::VectorXd> reading, kincal::MatrixXd* J_reading_pose,
               kincal::MatrixXd* J_reading_params) const override;

  bool has_manifold_readings() const override { return true; }
  void reading_error(const Eigen::Ref<const kincal::VectorXd>& predicted,
                     const Eigen::Ref<const kincal::VectorXd>& measured,
                     Eigen::Ref<kincal::VectorXd> error,
                     kincal::MatrixXd* J_error_predicted) const override;
  void retract(Eigen::Ref<kincal::VectorXd> reading,
               const Eigen::Ref<const kincal::VectorXd>& delta) const override;

 private:
  std::string name_;
  std::vector<kincal::Parameter> parameters_;
};

}  // namespace example
