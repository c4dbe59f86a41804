// The point tracker in model files:
//   { "type": "point-tracker", "name": "tracker",
//     "frame": { "position": [x, y, z], "rotation_zyx_deg": [rx, ry, rz] },
//     "target": [x, y, z] }
// frame: the tracker's frame in base coordinates (mm, degrees); target: the target point in
// the end effector's frame (mm).

#include "kincal/framework/model_registry.hpp"
#include "kincal/models/point_tracker.hpp"

namespace kincal {

namespace {

using namespace json_field;

std::shared_ptr<const Sensor> read_point_tracker(const Json& j, const JsonPath& where) {
  check_keys(j, where, {"type", "name", "frame", "target"});
  const std::string tracker_name = name(member(j, "name", where), where / "name");
  return std::make_shared<PointTracker>(tracker_name,
                                        frame(member(j, "frame", where), where / "frame"),
                                        vector3(member(j, "target", where), where / "target"));
}

Json write_point_tracker(const Sensor& sensor, const Eigen::Ref<const VectorXd>& values) {
  const auto frame = values.segment<6>(PointTracker::kFrameIndex);
  return {{"name", sensor.name()},
          {"frame", pose_json(frame.head<3>(), frame.tail<3>())},
          {"target", array3(values.segment<3>(PointTracker::kTargetIndex))}};
}

}  // namespace

void register_point_tracker(ModelRegistry& registry) {
  registry.add_sensor({"point-tracker",
                       "a target point on the end effector seen in a tracker frame (laser "
                       "tracker); three readings x, y, z in mm",
                       read_point_tracker, write_point_tracker});
}

}  // namespace kincal
