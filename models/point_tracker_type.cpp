// The point tracker in model files (framework/extension/generic_model_file.hpp, from its
// parameters):
//   { "type": "point-tracker", "name": "tracker",
//     "frame": { "position": [x, y, z], "rotation_zyx_deg": [rx, ry, rz] },
//     "target": [x, y, z] }
// frame: the tracker's frame in base coordinates (mm, degrees); target: the target point in
// the end effector's frame (mm).

#include "kincal/framework/extension/generic_model_file.hpp"
#include "kincal/models/point_tracker.hpp"

namespace kincal {

void register_point_tracker(ModelRegistry& registry) {
  const PointTracker prototype("tracker", Vector6d::Zero(), Vector3d::Zero());
  registry.add_sensor(generic_sensor_type(
      "point-tracker",
      "a target point on the end effector seen in a tracker frame (laser tracker); three "
      "readings x, y, z in mm",
      sensor_layout(prototype),
      [](const std::string& name, const VectorXd& v, const ModelFileOptions&) {
        return std::make_shared<PointTracker>(name, v.segment<6>(PointTracker::kFrameIndex),
                                              v.segment<3>(PointTracker::kTargetIndex));
      }));
}

}  // namespace kincal
