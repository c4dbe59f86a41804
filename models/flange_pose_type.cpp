// The flange-pose mechanism in model files:
//   "mechanism": { "type": "flange-pose",
//                  "home_pose": { "position": [x, y, z], "rotation_zyx_deg": [rx, ry, rz] },
//                  "range": { "position": 100, "rotation_deg": 20 } }
// home_pose (mm, degrees) and range (the half-widths of the box around it from which
// simulation and design draw flange poses; mm and degrees) are optional: the identity and
// 100 mm, 20 degrees.

#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/framework/io/json_input.hpp"
#include "kincal/models/flange_pose.hpp"

namespace kincal {

namespace {

using namespace json_field;

constexpr double kDefaultPositionRange = 100;  // mm
constexpr double kDefaultRotationRangeDeg = 20;

std::shared_ptr<const Mechanism> read_flange_pose(const Json& j, const JsonPath& where) {
  check_keys(j, where, {"type", "home_pose", "range"});
  Pose home;
  if (const Json* h = optional(j, "home_pose")) home = pose(*h, where / "home_pose");
  double position_range = kDefaultPositionRange;
  double rotation_range_deg = kDefaultRotationRangeDeg;
  if (const Json* r = optional(j, "range")) {
    const JsonPath at = where / "range";
    object(*r, at);
    check_keys(*r, at, {"position", "rotation_deg"});
    position_range = number_or(*r, "position", position_range, at);
    rotation_range_deg = number_or(*r, "rotation_deg", rotation_range_deg, at);
    if (!(position_range > 0)) (at / "position").fail("expected a positive half-width (mm)");
    if (!(rotation_range_deg > 0))
      (at / "rotation_deg").fail("expected a positive half-width (degrees)");
  }
  return std::make_shared<FlangePose>(home, position_range,
                                      radians_from_degrees(rotation_range_deg));
}

Json write_flange_pose(const Mechanism& mechanism, const Eigen::Ref<const VectorXd>&) {
  const auto& flange = dynamic_cast<const FlangePose&>(mechanism);
  Json out;
  out["home_pose"] = pose_json(flange.home_pose());
  out["range"] = {{"position", flange.position_range()},
                  {"rotation_deg", flange.rotation_range() * kDegreesPerRadian}};
  return out;
}

}  // namespace

void register_flange_pose(ModelRegistry& registry) {
  registry.add_mechanism({"flange-pose",
                          "a robot known by the flange poses its controller reports (no "
                          "parameters): columns flange.x, .y, .z (mm) and flange.rotvec_x, _y, "
                          "_z (rad)",
                          read_flange_pose, write_flange_pose});
}

}  // namespace kincal
