#include "inclinometer.hpp"

#include <cmath>
#include <kincal/framework/kinematics/units.hpp>

namespace example {

using namespace kincal;

Inclinometer::Inclinometer(std::string name, double offset) : name_(std::move(name)) {
  parameters_ = {{name_ + ".offset", offset, kRadian}};
}

void Inclinometer::predict(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                           Eigen::Ref<VectorXd> reading, MatrixXd* J_reading_pose,
                           MatrixXd* J_reading_params) const {
  const Vector3d c = pose.rotation.col(0);  // the end effector's x axis, base coordinates
  reading[0] = wrap_angle(std::atan2(c.y(), c.x()) + params[0]);
  if (J_reading_pose) {
    // d atan2(c_y, c_x) under R <- exp([dw]x) R, dc = dw x c.
    const double rho = c.x() * c.x() + c.y() * c.y();
    J_reading_pose->setZero();
    (*J_reading_pose)(0, 3) = -c.x() * c.z() / rho;
    (*J_reading_pose)(0, 4) = -c.y() * c.z() / rho;
    (*J_reading_pose)(0, 5) = 1.0;
  }
  if (J_reading_params) (*J_reading_params)(0, 0) = 1.0;
}

void Inclinometer::reading_error(const Eigen::Ref<const VectorXd>& predicted,
                                 const Eigen::Ref<const VectorXd>& measured,
                                 Eigen::Ref<VectorXd> error, MatrixXd* J_error_predicted) const {
  error[0] = wrap_angle(predicted[0] - measured[0]);
  if (J_error_predicted) J_error_predicted->setIdentity();
}

void Inclinometer::retract(Eigen::Ref<VectorXd> reading,
                           const Eigen::Ref<const VectorXd>& delta) const {
  reading[0] = wrap_angle(reading[0] + delta[0]);
}

}  // namespace example
