// The one place that knows which model types kincal ships: one registration line per
// mechanism or sensor type (each registers its JSON reader/writer and its presets).

#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/models/camera.hpp"
#include "kincal/models/fixture_distance.hpp"
#include "kincal/models/flange_pose.hpp"
#include "kincal/models/hexapod.hpp"
#include "kincal/models/length_gauge.hpp"
#include "kincal/models/planar_3rpr.hpp"
#include "kincal/models/point_tracker.hpp"
#include "kincal/models/pose_tracker.hpp"
#include "kincal/models/serial_arm.hpp"
#include "kincal/models/socket.hpp"
#include "kincal/models/urdf_arm.hpp"

namespace kincal {

void register_builtin_models(ModelRegistry& registry) {
  register_hexapod(registry);
  register_planar_3rpr(registry);
  register_flange_pose(registry);
  register_serial_arm(registry);
  register_urdf_arm(registry);
  register_length_gauge(registry);
  register_point_tracker(registry);
  register_pose_tracker(registry);
  register_socket(registry);
  register_camera(registry);
  register_fixture_distance(registry);
}

}  // namespace kincal
