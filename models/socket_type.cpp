// The socket in model files (framework/extension/generic_model_file.hpp, from its parameters):
//   { "type": "socket", "name": "socket0", "point": [x, y, z] }
// point: the socket's centre in base coordinates (mm). And the preset ur5-urdf-socket.

#include <cmath>

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
  auto socket = std::make_shared<Socket>("socket", Vector3d(-400, -100, 300));
  auto model = std::make_shared<MeasurementModel>(
      arm_model->mechanism_ptr(), std::vector<std::shared_ptr<const Sensor>>{socket});
  // The free set as ur5-urdf chooses its own, on other configurations.
  free_what_home_configurations_determine(*model, 1.3, 1.9, 0.2);
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
