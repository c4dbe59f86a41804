#pragma once
// A socket: a fixture whose position is unknown, into which the mechanism's tool point (the
// origin of its end pose: for an arm the tool frame, e.g. the centre of a ball on the
// flange) is put in some configurations. Only the actuators are recorded; the readings are
// the gap between the tool point and the socket's centre p (base coordinates):
//   reading = t - p        three readings <name>.x, .y, .z (mm), measured as 0
// for the mechanism's pose (R, t). p is one unknown shared by every configuration measured
// in this socket, so a calibration makes the tool points of those configurations coincide.
// Several sockets are several sensors; a configuration taken in one socket has no reading
// (NaN) for the others. Scale comes from elsewhere (a fixture-distance constraint,
// models/fixture_distance.hpp): a socket alone does not fix it.
// Parameters: <name>.point.{x, y, z} (mm).

#include "kincal/framework/kinematics/sensor.hpp"

namespace kincal {

class ModelRegistry;

class Socket final : public Sensor {
 public:
  /// `point`: the socket's centre in base coordinates (mm). Fixed by default.
  Socket(std::string name, const Vector3d& point);

  std::string type() const override { return "socket"; }
  const std::string& name() const override { return name_; }
  int num_readings() const override { return 3; }
  std::vector<std::string> reading_names() const override;
  std::vector<std::string> reading_units() const override;
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  /// The readings are the tool point's position relative to the socket.
  int position_reading_index() const override { return 0; }
  /// ... in the measurement frame (base coordinates), measured as 0: turning the whole setup
  /// changes no fit (a gauge freedom, docs/theory.md).
  int frame_vector_reading_index() const override { return 0; }

  void predict(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
               Eigen::Ref<VectorXd> reading, MatrixXd* J_reading_pose,
               MatrixXd* J_reading_params) const override;

  static constexpr int kPointIndex = 0;

 private:
  std::string name_;
  std::vector<Parameter> parameters_;
};

/// Registers the type (model-file reader/writer) and the preset ur5-urdf-socket.
void register_socket(ModelRegistry& registry);

}  // namespace kincal
