// The pose tracker in model files (framework/extension/generic_model_file.hpp, from its
// parameters):
//   { "type": "pose-tracker", "name": "camera",
//     "frame": { "position": [x, y, z], "rotation_zyx_deg": [rx, ry, rz] },
//     "marker": { "position": [x, y, z], "rotation_zyx_deg": [rx, ry, rz] } }
// frame: the tracker's frame in base coordinates; marker: the marker's frame in the end
// effector's frame (mm, degrees).

#include "kincal/framework/extension/generic_model_file.hpp"
#include "kincal/models/pose_tracker.hpp"

namespace kincal {

void register_pose_tracker(ModelRegistry& registry) {
  const PoseTracker prototype("camera", Vector6d::Zero(), Vector6d::Zero());
  registry.add_sensor(generic_sensor_type(
      "pose-tracker",
      "a marker frame on the end effector seen in a tracker frame (optical tracker, camera); "
      "readings x, y, z in mm and the rotation vector rx, ry, rz in rad, residual on SE(3)",
      sensor_layout(prototype),
      [](const std::string& name, const VectorXd& v, const ModelFileOptions&) {
        return std::make_shared<PoseTracker>(name, v.segment<6>(PoseTracker::kFrameIndex),
                                             v.segment<6>(PoseTracker::kMarkerIndex));
      }));
}

}  // namespace kincal
