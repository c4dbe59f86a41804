#pragma once
// One configuration of the implicit-loop formulation (docs/theory.md): its pose is an unknown,
// and its residuals are the closed chain's closure constraints g(params, q, pose) and the
// sensors' whitened reading errors at that pose, with Jacobians in the chain's local pose
// coordinates. Shared by ImplicitCalibrationProblem (generic rows) and the Schur-complement
// lm (solvers/schur_levenberg_marquardt.cpp). Scratch is sized once per model: nothing is
// allocated per configuration once warm.

#include <cmath>
#include <limits>
#include <string>

#include "kincal/framework/kinematics/closed_chain_mechanism.hpp"
#include "kincal/framework/kinematics/measurement_model.hpp"

namespace kincal {

template <int Dof>
struct ImplicitConfiguration {
  using ConstraintVector = Eigen::Matrix<double, Dof, 1>;
  using ConstraintJacobian = Eigen::Matrix<double, Dof, Dof>;

  ConstraintVector g;         ///< closure constraints, unweighted (the constraints' units)
  ConstraintJacobian G_pose;  ///< dg / d local pose
  VectorXd errors;            ///< whitened reading errors; 0 where nothing was measured
  Eigen::Matrix<double, Eigen::Dynamic, Dof> H_pose;  ///< d errors / d local pose (k x Dof)
  /// d errors / d parameters (k x all parameters): only the sensors' own columns, as the
  /// mechanism's parameters reach the readings through the pose, an unknown here.
  MatrixXd H_params;

  // Scratch.
  VectorXd predicted, measured;
  MatrixXd J_reading;  ///< k x (6 + all parameters): [d reading / d pose | d reading / d params]
  std::vector<MatrixXd> J_sensor_pose, J_sensor_params;

  /// Sizes everything for `model` (no-op when it already fits).
  void prepare(const MeasurementModel& model) {
    const int k = model.num_readings(), n = model.num_parameters();
    errors.resize(k);
    H_pose.resize(k, Dof);
    H_params.resize(k, n);
    predicted.resize(k);
    measured.resize(k);
    J_reading.resize(k, 6 + n);
    const auto& sensors = model.sensors();
    J_sensor_pose.resize(sensors.size());
    J_sensor_params.resize(sensors.size());
    for (std::size_t s = 0; s < sensors.size(); ++s) {
      J_sensor_pose[s].resize(sensors[s]->num_readings(), 6);
      J_sensor_params[s].resize(sensors[s]->num_readings(), sensors[s]->num_parameters());
    }
  }
};

/// Fills `out` for configuration `block` (actuators q, measured readings `measured_row`) at
/// `pose` with the full parameter vector `params`; the Jacobians only when `jacobians`. With
/// `constraints_known`, out.g (and out.G_pose when `jacobians`) already hold the constraints
/// at `pose` and are kept.
/// False, with "sensor NAME: no reading: ..." in `why`, when a measured reading cannot be
/// taken at the pose (the nested problem fails there too).
template <int Dof>
bool evaluate_implicit_configuration(
    const MeasurementModel& model, const ClosedChainMechanism<Dof>& mechanism,
    const Eigen::Ref<const VectorXd>& params, const ActuatorsRef& q,
    const Eigen::Ref<const VectorXd, 0, Eigen::InnerStride<>>& measured_row, const Pose& pose,
    bool jacobians, ImplicitConfiguration<Dof>& out, std::string* why,
    bool constraints_known = false) {
  out.prepare(model);
  const int n_mech = mechanism.num_parameters();
  if (!constraints_known)
    mechanism.constraints(params.head(n_mech), q, pose, out.g, jacobians ? &out.G_pose : nullptr);
  out.measured = measured_row;
  const auto& sensors = model.sensors();
  const int n = model.num_parameters();
  if (jacobians) out.J_reading.setZero();
  for (std::size_t s = 0; s < sensors.size(); ++s) {
    const Sensor& sensor = *sensors[s];
    const int k = sensor.num_readings(), o = model.sensor_reading_offset(static_cast<int>(s));
    const int po = model.sensor_parameter_offset(static_cast<int>(s));
    const auto sensor_params = params.segment(po, sensor.num_parameters());
    if (out.measured.segment(o, k).array().isNaN().all()) {
      out.predicted.segment(o, k).setConstant(std::numeric_limits<double>::quiet_NaN());
      continue;  // not measured: reading_errors gives zero rows
    }
    if (sensor.can_miss()) {
      std::string reason;
      if (!sensor.reads_at(sensor_params, pose, why ? &reason : nullptr)) {
        if (why) *why = "sensor " + sensor.name() + ": no reading: " + reason;
        return false;
      }
    }
    sensor.predict(sensor_params, pose, out.predicted.segment(o, k),
                   jacobians ? &out.J_sensor_pose[s] : nullptr,
                   jacobians ? &out.J_sensor_params[s] : nullptr);
    if (jacobians) {
      out.J_reading.block(o, 0, k, 6) = out.J_sensor_pose[s];
      out.J_reading.block(o, 6 + po, k, sensor.num_parameters()) = out.J_sensor_params[s];
    }
  }
  Eigen::Ref<MatrixXd> J_ref(out.J_reading);
  model.reading_errors(out.predicted, out.measured, out.errors, jacobians ? &J_ref : nullptr);
  if (model.weighted()) {
    out.errors.array() /= model.reading_std().array();
    if (jacobians) out.J_reading.array().colwise() /= model.reading_std().array();
  }
  if (jacobians) {
    if constexpr (Dof == 6)
      out.H_pose = out.J_reading.leftCols(6);
    else
      out.H_pose.noalias() = out.J_reading.leftCols(6) * mechanism.motion_basis();
    out.H_params = out.J_reading.rightCols(n);
  }
  return true;
}

/// The pose `reference` moved by local coordinates `local` (ClosedChainMechanism::moved).
template <int Dof>
Pose moved_pose(const ClosedChainMechanism<Dof>& mechanism, const Pose& reference,
                const Eigen::Matrix<double, Dof, 1>& local) {
  if constexpr (Dof == 6) return perturb(reference, local);
  return perturb(reference, mechanism.motion_basis() * local);
}

}  // namespace kincal
