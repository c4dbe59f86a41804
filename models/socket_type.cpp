// The socket in model files (framework/extension/generic_model_file.hpp, from its parameters):
//   { "type": "socket", "name": "socket0", "point": [x, y, z] }
// point: the socket's centre in base coordinates (mm). And the preset ur5-urdf-socket.

#include <cmath>

#include "kincal/framework/analysis/identifiability.hpp"
#include "kincal/framework/extension/generic_model_file.hpp"
#include "kincal/models/socket.hpp"
#include "kincal/models/urdf_arm.hpp"

namespace kincal {

namespace {

// The ur5-urdf arm with one socket in its workspace. A simulation of it reads the tool point
// relative to the socket wherever the arm is (as a tracker that sees no rotation would), so
// the conformance checks can hold the socket to a recovery; real socket data put the tool
// in the socket and read 0 (examples/robot_sockets).
std::shared_ptr<MeasurementModel> make_ur5_urdf_socket() {
  const auto arm_model = make_ur5_urdf();
  const auto& arm = static_cast<const UrdfArm&>(arm_model->mechanism());
  auto socket = std::make_shared<Socket>("socket", Vector3d(-400, -100, 300));
  auto model = std::make_shared<MeasurementModel>(
      arm_model->mechanism_ptr(), std::vector<std::shared_ptr<const Sensor>>{socket});
  // The free set: what a pivoted QR of the identification Jacobian keeps at nominal, on 30
  // fixed configurations around home (as ur5-urdf chooses its own).
  const VectorXd nominal = model->parameters().nominal_values();
  VectorXd home(arm.num_joints()), q(arm.num_joints()), readings(model->num_readings());
  arm.home_actuators(nominal, home);
  auto ws = model->make_workspace();
  const int configurations = 30;
  MatrixXd J(configurations * model->num_readings(), model->num_parameters());
  MatrixXd block(model->num_readings(), model->num_parameters());
  for (int c = 0; c < configurations; ++c) {
    for (int i = 0; i < q.size(); ++i)
      q[i] = home[i] + UrdfArm::kDefaultRevoluteRange * std::sin(1.3 * c + 1.9 * i + 0.2 * c * i);
    Eigen::Ref<MatrixXd> ref(block);
    model->predict(nominal, q, readings, &ref, ws);
    J.middleRows(c * model->num_readings(), model->num_readings()) = block;
  }
  for (int i : identifiable_subset(J, urdf_arm_parameter_priority(*model)))
    model->parameters().set_free(model->parameters()[i].name, true);
  return model;
}

}  // namespace

void register_socket(ModelRegistry& registry) {
  const Socket prototype("socket", Vector3d::Zero());
  registry.add_sensor(generic_sensor_type(
      "socket",
      "an unknown fixture point (a socket) that the tool point is put into; three readings x, "
      "y, z in mm, the tool point minus the socket's centre, measured as 0",
      sensor_layout(prototype),
      [](const std::string& name, const VectorXd& v, const ModelFileOptions&) {
        return std::make_shared<Socket>(name, v.segment<3>(Socket::kPointIndex));
      }));
  registry.add_preset({"ur5-urdf-socket",
                       "the ur5-urdf arm with one socket (sensor type socket) in its workspace; "
                       "a simulation reads the tool point relative to the socket",
                       make_ur5_urdf_socket});
}

}  // namespace kincal
