#pragma once
// What the sensor tests build their sensors from: a frame block's six values, and a sensor's
// own parameter vector at its nominal values.

#include "kincal/framework/kinematics/sensor.hpp"

namespace kincal::testing {

/// [x, y, z, rx, ry, rz]: a frame parameter block (frame_from_parameters).
inline Vector6d frame_params(const Vector3d& position, const Vector3d& rx_ry_rz) {
  Vector6d p;
  p << position, rx_ry_rz;
  return p;
}

/// The sensor's parameters at their nominal values, in its own order.
inline VectorXd params_of(const Sensor& sensor) {
  VectorXd p(sensor.num_parameters());
  for (int i = 0; i < sensor.num_parameters(); ++i) p[i] = sensor.parameters()[i].nominal;
  return p;
}

}  // namespace kincal::testing
