#include "kincal/framework/kinematics/sensor.hpp"

namespace kincal {

void Sensor::reading_error(const Eigen::Ref<const VectorXd>& predicted,
                           const Eigen::Ref<const VectorXd>& measured, Eigen::Ref<VectorXd> error,
                           MatrixXd* J_error_predicted) const {
  error = predicted - measured;
  if (J_error_predicted) J_error_predicted->setIdentity();
}

int Sensor::drop_unseen(const Eigen::Ref<const VectorXd>&, const Pose&,
                        Eigen::Ref<VectorXd>) const {
  return 0;
}

bool Sensor::valid_reading(int, double, std::string*) const { return true; }

bool Sensor::reads_at(const Eigen::Ref<const VectorXd>&, const Pose&, std::string*) const {
  return true;
}

void Sensor::retract(Eigen::Ref<VectorXd> reading, const Eigen::Ref<const VectorXd>& delta) const {
  reading += delta;
}

}  // namespace kincal
