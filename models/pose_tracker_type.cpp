// The pose tracker in model files:
//   { "type": "pose-tracker", "name": "camera",
//     "frame": { "position": [x, y, z], "rotation_zyx_deg": [rx, ry, rz] },
//     "marker": { "position": [x, y, z], "rotation_zyx_deg": [rx, ry, rz] } }
// frame: the tracker's frame in base coordinates; marker: the marker's frame in the end
// effector's frame (mm, degrees).

#include "kincal/framework/model_registry.hpp"
#include "kincal/models/pose_tracker.hpp"

namespace kincal {

namespace {

using namespace json_field;

std::shared_ptr<const Sensor> read_pose_tracker(const Json& j, const JsonPath& where) {
  check_keys(j, where, {"type", "name", "frame", "marker"});
  const std::string tracker_name = name(member(j, "name", where), where / "name");
  return std::make_shared<PoseTracker>(tracker_name,
                                       frame(member(j, "frame", where), where / "frame"),
                                       frame(member(j, "marker", where), where / "marker"));
}

Json write_pose_tracker(const Sensor& sensor, const Eigen::Ref<const VectorXd>& values) {
  const auto frame = values.segment<6>(PoseTracker::kFrameIndex);
  const auto marker = values.segment<6>(PoseTracker::kMarkerIndex);
  return {{"name", sensor.name()},
          {"frame", pose_json(frame.head<3>(), frame.tail<3>())},
          {"marker", pose_json(marker.head<3>(), marker.tail<3>())}};
}

}  // namespace

void register_pose_tracker(ModelRegistry& registry) {
  registry.add_sensor({"pose-tracker",
                       "a marker frame on the end effector seen in a tracker frame (optical "
                       "tracker, camera); readings x, y, z in mm and the rotation vector rx, "
                       "ry, rz in rad, residual on SE(3)",
                       read_pose_tracker, write_pose_tracker});
}

}  // namespace kincal
