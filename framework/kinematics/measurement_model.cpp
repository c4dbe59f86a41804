#include "kincal/framework/kinematics/measurement_model.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace kincal {

MeasurementModel::MeasurementModel(std::shared_ptr<const Mechanism> mechanism,
                                   std::vector<std::shared_ptr<const Sensor>> sensors)
    : mechanism_(std::move(mechanism)), sensors_(std::move(sensors)) {
  if (!mechanism_) throw std::invalid_argument("measurement model needs a mechanism");
  if (sensors_.empty()) throw std::invalid_argument("measurement model needs a sensor");
  parameters_.append(mechanism_->parameters());
  for (const auto& sensor : sensors_) {
    if (!sensor) throw std::invalid_argument("measurement model: null sensor");
    sensor_offsets_.push_back(parameters_.size());
    parameters_.append(sensor->parameters());
    reading_offsets_.push_back(num_readings_);
    num_readings_ += sensor->num_readings();
    has_manifold_readings_ = has_manifold_readings_ || sensor->has_manifold_readings();
    sensors_can_miss_ = sensors_can_miss_ || sensor->can_miss();
  }
  reading_std_ = VectorXd::Ones(num_readings_);
  const auto& actuators = mechanism_->actuators();
  actuator_ranges_.resize(static_cast<int>(actuators.size()));
  for (std::size_t i = 0; i < actuators.size(); ++i)
    actuator_ranges_[static_cast<int>(i)] = actuators[i].default_range;
}

std::vector<std::string> MeasurementModel::reading_units() const {
  std::vector<std::string> units;
  for (const auto& sensor : sensors_)
    for (auto& u : sensor->reading_units()) units.push_back(u);
  return units;
}

void MeasurementModel::add_constraint(std::shared_ptr<const ParameterConstraint> constraint) {
  std::vector<int> indices;
  for (const auto& name : constraint->parameter_names())
    indices.push_back(parameters_.index_of(name));
  constraints_.push_back(std::move(constraint));
  constraint_indices_.push_back(std::move(indices));
}

int MeasurementModel::set_reading_std(const std::string& pattern, double std) {
  // The same bounds as a prior's std: beyond them the whitened residuals r / std and the
  // weights 1 / std^2 overflow or vanish (a reading_std of 1e-300 made the cost overflow and
  // was blamed on the readings).
  if (!(std >= kMinPriorStd && std <= kMaxPriorStd))
    throw std::invalid_argument("reading std for '" + pattern +
                                "' must be between 1e-150 and 1e150");
  int count = 0;
  const auto names = reading_names();
  for (int i = 0; i < num_readings_; ++i) {
    if (!glob_match(pattern, names[i])) continue;
    reading_std_[i] = std;
    ++count;
  }
  if (count == 0)
    throw std::invalid_argument("reading pattern '" + pattern + "' matches no reading");
  return count;
}

int MeasurementModel::set_actuator_range(const std::string& pattern, double half_width) {
  if (!(half_width >= 0) || !std::isfinite(half_width))
    throw std::invalid_argument("actuator range for '" + pattern +
                                "' must be a finite number >= 0");
  int count = 0;
  const auto& actuators = mechanism_->actuators();
  for (std::size_t i = 0; i < actuators.size(); ++i) {
    if (!glob_match(pattern, actuators[i].name)) continue;
    actuator_ranges_[static_cast<int>(i)] = half_width;
    ++count;
  }
  if (count == 0)
    throw std::invalid_argument("actuator pattern '" + pattern + "' matches no actuator");
  return count;
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
                                                  Eigen::Ref<MatrixXd>* J, Workspace& ws,
                                                  const Pose* start, int max_newton_steps) const {
  const int n_mech = mechanism_->num_parameters();
  const auto mech_params = params.head(n_mech);
  ForwardKinematicsOptions options = fk_options_;
  if (max_newton_steps >= 0) options.max_iterations = max_newton_steps;
  const ForwardKinematicsResult fk = mechanism_->forward_kinematics(
      mech_params, q, start ? *start : mechanism_->home_pose(), options);
  if (!fk.ok()) return fk;

  if (J) prepare(ws);
  int row = 0;
  for (std::size_t s = 0; s < sensors_.size(); ++s) {
    const Sensor& sensor = *sensors_[s];
    const int k = sensor.num_readings();
    const auto sensor_params = params.segment(sensor_offsets_[s], sensor.num_parameters());
    if (sensors_can_miss_ && sensor.can_miss() &&
        !sensor.reads_at(sensor_params, fk.pose, nullptr)) {
      // No reading: NaN, and no gradient through it (reading_errors then drops it).
      readings.segment(row, k).setConstant(std::numeric_limits<double>::quiet_NaN());
      if (J) {
        ws.J_readings_pose.middleRows(row, k).setZero();
        J->middleRows(row, k).setZero();
      }
      row += k;
      continue;
    }
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
    if (sensor.can_miss() && !sensor.reads_at(sensor_params, pose, nullptr))
      readings.segment(row, sensor.num_readings())
          .setConstant(std::numeric_limits<double>::quiet_NaN());
    else
      sensor.predict(sensor_params, pose, readings.segment(row, sensor.num_readings()), nullptr,
                     nullptr);
    row += sensor.num_readings();
  }
}

int MeasurementModel::simulate_at_pose(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                                       Eigen::Ref<VectorXd> readings) const {
  predict_at_pose(params, pose, readings);
  if (!sensors_can_miss_) return 0;
  int missing = 0, row = 0;
  for (std::size_t s = 0; s < sensors_.size(); ++s) {
    const Sensor& sensor = *sensors_[s];
    const int k = sensor.num_readings();
    if (sensor.can_miss()) {
      auto own = readings.segment(row, k);
      if (std::isnan(own[0]))
        missing += k;  // the sensor does not read there (predict_at_pose)
      else
        missing += sensor.drop_unseen(params.segment(sensor_offsets_[s], sensor.num_parameters()),
                                      pose, own);
    }
    row += k;
  }
  return missing;
}

bool MeasurementModel::sensor_reads_at(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                                       int sensor_index, std::string* reason) const {
  const Sensor& sensor = *sensors_.at(sensor_index);
  return !sensor.can_miss() ||
         sensor.reads_at(params.segment(sensor_offsets_[sensor_index], sensor.num_parameters()),
                         pose, reason);
}

std::vector<int> MeasurementModel::identification_priority() const {
  std::vector<int> mechanism = mechanism_->identification_priority();
  if (mechanism.empty()) return {};
  if (mechanism.size() != mechanism_->parameters().size())
    throw std::logic_error("mechanism type " + mechanism_->type() +
                           ": identification_priority has " + std::to_string(mechanism.size()) +
                           " entries for " + std::to_string(mechanism_->parameters().size()) +
                           " parameters");
  mechanism.resize(static_cast<std::size_t>(num_parameters()), 0);  // the sensors' after it
  for (std::size_t s = 0; s < sensors_.size(); ++s)
    if (sensors_[s]->frame_vector_reading_index() >= 0)
      for (int i = 0; i < sensors_[s]->num_parameters(); ++i)
        mechanism[static_cast<std::size_t>(sensor_offsets_[s] + i)] = -1;
  return mechanism;
}

int MeasurementModel::sensor_of_reading(int reading_index) const {
  int s = 0;
  while (s + 1 < static_cast<int>(sensors_.size()) && reading_offsets_[s + 1] <= reading_index) ++s;
  return s;
}

void MeasurementModel::reading_errors(const Eigen::Ref<const VectorXd>& predicted,
                                      const Eigen::Ref<const VectorXd>& measured,
                                      Eigen::Ref<VectorXd> errors, Eigen::Ref<MatrixXd>* J) const {
  if (!has_manifold_readings_) {
    // The common case, kept free of per-sensor calls: plain differences.
    for (int i = 0; i < num_readings_; ++i) {
      if (std::isnan(measured[i])) {
        errors[i] = 0;
        if (J) J->row(i).setZero();
      } else {
        errors[i] = predicted[i] - measured[i];
      }
    }
    return;
  }
  thread_local MatrixXd J_error_predicted, rows;
  for (std::size_t s = 0; s < sensors_.size(); ++s) {
    const Sensor& sensor = *sensors_[s];
    const int k = sensor.num_readings(), o = reading_offsets_[s];
    if (measured.segment(o, k).array().isNaN().any()) {
      // Readers accept a sensor's readings all present or all missing.
      errors.segment(o, k).setZero();
      if (J) J->middleRows(o, k).setZero();
      continue;
    }
    if (!sensor.has_manifold_readings()) {
      errors.segment(o, k) = predicted.segment(o, k) - measured.segment(o, k);
      continue;
    }
    J_error_predicted.resize(k, k);
    sensor.reading_error(predicted.segment(o, k), measured.segment(o, k), errors.segment(o, k),
                         J ? &J_error_predicted : nullptr);
    if (J) {
      rows.noalias() = J_error_predicted * J->middleRows(o, k);
      J->middleRows(o, k) = rows;
    }
  }
}

void MeasurementModel::retract(Eigen::Ref<VectorXd> readings,
                               const Eigen::Ref<const VectorXd>& delta) const {
  for (std::size_t s = 0; s < sensors_.size(); ++s) {
    const int k = sensors_[s]->num_readings(), o = reading_offsets_[s];
    sensors_[s]->retract(readings.segment(o, k), delta.segment(o, k));
  }
}

}  // namespace kincal
