#include "kincal/framework/measurement_model.hpp"

#include <stdexcept>

namespace kincal {

MeasurementModel::MeasurementModel(std::shared_ptr<const Mechanism> mechanism,
                                   std::vector<std::shared_ptr<const Sensor>> sensors)
    : mechanism_(std::move(mechanism)), sensors_(std::move(sensors)) {
  if (!mechanism_) throw std::invalid_argument("measurement model needs a mechanism");
  if (sensors_.empty()) throw std::invalid_argument("measurement model needs a sensor");
  parameters_.append(mechanism_->parameters());
  for (const auto& sensor : sensors_) {
    sensor_offsets_.push_back(parameters_.size());
    parameters_.append(sensor->parameters());
    num_readings_ += sensor->num_readings();
  }
}

std::vector<std::string> MeasurementModel::reading_names() const {
  std::vector<std::string> names;
  for (const auto& sensor : sensors_)
    for (auto& n : sensor->reading_names()) names.push_back(n);
  return names;
}

MeasurementModel::Workspace MeasurementModel::make_workspace() const {
  Workspace ws;
  prepare(ws);
  return ws;
}

void MeasurementModel::prepare(Workspace& ws) const {
  ws.J_readings_pose.resize(num_readings_, 6);
  ws.J_reading_pose.resize(sensors_.size());
  ws.J_reading_params.resize(sensors_.size());
  for (std::size_t s = 0; s < sensors_.size(); ++s) {
    ws.J_reading_pose[s].resize(sensors_[s]->num_readings(), 6);
    ws.J_reading_params[s].resize(sensors_[s]->num_readings(), sensors_[s]->num_parameters());
  }
}

ForwardKinematicsResult MeasurementModel::predict(const Eigen::Ref<const VectorXd>& params,
                                                  const ActuatorsRef& q,
                                                  Eigen::Ref<VectorXd> readings,
                                                  Eigen::Ref<MatrixXd>* J, Workspace& ws) const {
  const int n_mech = mechanism_->num_parameters();
  const auto mech_params = params.head(n_mech);
  const ForwardKinematicsResult fk =
      mechanism_->forward_kinematics(mech_params, q, mechanism_->home_pose(), fk_options_);
  if (!fk.ok()) return fk;

  if (J) prepare(ws);
  int row = 0;
  for (std::size_t s = 0; s < sensors_.size(); ++s) {
    const Sensor& sensor = *sensors_[s];
    const int k = sensor.num_readings();
    const auto sensor_params = params.segment(sensor_offsets_[s], sensor.num_parameters());
    sensor.predict(sensor_params, fk.pose, readings.segment(row, k),
                   J ? &ws.J_reading_pose[s] : nullptr, J ? &ws.J_reading_params[s] : nullptr);
    if (J) {
      ws.J_readings_pose.middleRows(row, k) = ws.J_reading_pose[s];
      J->middleCols(n_mech, J->cols() - n_mech).middleRows(row, k).setZero();
      J->block(row, sensor_offsets_[s], k, sensor.num_parameters()) = ws.J_reading_params[s];
    }
    row += k;
  }
  // Chain rule through the mechanism: J_readings_pose * J_pose_params, which a closed chain
  // forms without J_pose_params (adjoint form, see ClosedChainMechanism).
  if (J)
    mechanism_->output_jacobian_params(mech_params, q, fk.pose, ws.J_readings_pose,
                                       J->leftCols(n_mech));
  return fk;
}

void MeasurementModel::predict_at_pose(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                                       Eigen::Ref<VectorXd> readings) const {
  int row = 0;
  for (std::size_t s = 0; s < sensors_.size(); ++s) {
    const Sensor& sensor = *sensors_[s];
    const auto sensor_params = params.segment(sensor_offsets_[s], sensor.num_parameters());
    sensor.predict(sensor_params, pose, readings.segment(row, sensor.num_readings()), nullptr,
                   nullptr);
    row += sensor.num_readings();
  }
}

}  // namespace kincal
