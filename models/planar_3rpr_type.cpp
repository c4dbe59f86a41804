// The planar 3-RPR robot in model files and its preset.
//   "mechanism": { "type": "planar-3rpr",
//                  "home_pose": { "position": [x, y], "rotation_deg": theta },
//                  "legs": [ { "name": "leg1", "base": [x, y], "platform": [x, y],
//                              "offset": 0 }, ... three ] }

#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/framework/io/json_input.hpp"
#include "kincal/models/length_gauge.hpp"
#include "kincal/models/planar_3rpr.hpp"

namespace kincal {

namespace {

using namespace json_field;

Eigen::Vector2d vector2(const Json& value, const JsonPath& where) {
  if (!value.is_array() || value.size() != 2)
    where.fail("expected an array of 2 numbers [x, y] (the robot moves in the plane z = 0), got " +
               json_excerpt(value));
  return Eigen::Vector2d(number(value[0], where[0]), number(value[1], where[1]));
}

// "+ 0.0" turns -0 into 0 so that files do not show "-0.0".
Json array2(const Eigen::Vector2d& v) { return Json::array({v[0] + 0.0, v[1] + 0.0}); }

PlanarPose planar_pose(const Json& value, const JsonPath& where) {
  object(value, where);
  check_keys(value, where, {"position", "rotation_deg"});
  const Eigen::Vector2d position = vector2(member(value, "position", where), where / "position");
  PlanarPose pose;
  pose.x = position.x();
  pose.y = position.y();
  pose.theta =
      radians_from_degrees(number(member(value, "rotation_deg", where), where / "rotation_deg"));
  return pose;
}

Json planar_pose_json(const PlanarPose& pose) {
  return {{"position", array2(Eigen::Vector2d(pose.x, pose.y))},
          {"rotation_deg",
           degrees_reading_back(pose.theta, pose.theta * kDegreesPerRadian, radians_from_degrees) +
               0.0}};
}

std::shared_ptr<const Mechanism> read_planar_3rpr(const Json& j, const JsonPath& where) {
  check_keys(j, where, {"type", "home_pose", "legs"});
  Planar3RprGeometry g;
  g.home = planar_pose(member(j, "home_pose", where), where / "home_pose");
  const Json& legs = member(j, "legs", where);
  if (!legs.is_array() || legs.size() != Planar3Rpr::kLegs)
    (where / "legs").fail("expected an array of 3 leg objects");
  for (int leg = 0; leg < Planar3Rpr::kLegs; ++leg) {
    const JsonPath at = (where / "legs")[leg];
    const Json& l = legs[leg];
    if (!l.is_object()) at.fail("expected an object with base, platform, offset");
    check_keys(l, at, {"name", "base", "platform", "offset"});
    const std::string expected_name = "leg" + std::to_string(leg + 1);
    if (l.contains("name") && l["name"] != expected_name)
      (at / "name").fail("expected \"" + expected_name + "\" (legs are listed in order)");
    g.base_joints[leg] = vector2(member(l, "base", at), at / "base");
    g.platform_joints[leg] = vector2(member(l, "platform", at), at / "platform");
    g.leg_offsets[leg] = number_or(l, "offset", 0.0, at);
  }
  return std::make_shared<Planar3Rpr>(g);
}

Json write_planar_3rpr(const Mechanism& mechanism, const Eigen::Ref<const VectorXd>& values) {
  const auto& robot = dynamic_cast<const Planar3Rpr&>(mechanism);
  Json out;
  out["home_pose"] = planar_pose_json(robot.nominal_geometry().home);
  out["legs"] = Json::array();
  for (int leg = 0; leg < Planar3Rpr::kLegs; ++leg)
    out["legs"].push_back({{"name", robot.actuators()[leg].name},
                           {"base", array2(values.segment<2>(Planar3Rpr::base_index(leg)))},
                           {"platform", array2(values.segment<2>(Planar3Rpr::platform_index(leg)))},
                           {"offset", values[Planar3Rpr::offset_index(leg)]}});
  return out;
}

// The experimental prototype of S. Schulz (Hamburg University of Technology), "On Using
// Inertial Measurement Units for Solving the Direct Kinematics Problem of Parallel
// Mechanisms", Robotics 8(4):99, 2019: base joints (40, 20), (340, 0), (0, 300) mm,
// platform joints (0, 0), (60, 0), (0, 60) mm, legs 168.4 mm long at zero stroke and
// 170-265 mm in use, values as in the authors' published prototype code (their motion plane
// is x-z; here it is x-y).
std::shared_ptr<MeasurementModel> make_planar_3rpr() {
  Planar3RprGeometry g;
  g.base_joints = {Eigen::Vector2d(40, 20), Eigen::Vector2d(340, 0), Eigen::Vector2d(0, 300)};
  g.platform_joints = {Eigen::Vector2d(0, 0), Eigen::Vector2d(60, 0), Eigen::Vector2d(0, 60)};
  g.leg_offsets = {168.4, 168.4, 168.4};
  // Home: the prototype's 60 mm platform is small against its 340 mm base. At (230, 180),
  // theta = 0, a pose the authors commanded, the three leg lines pass within 6 mm of one
  // point (near a singularity), and with the 5 mm parameter errors of a simulation forward
  // kinematics from there failed. Here they miss each other's crossing by 76 mm, and the
  // legs (194, 210 and 229 mm) are at least 24 mm from either end of their stroke.
  g.home = {150, 180, -70 * kPi / 180};
  auto robot = std::make_shared<Planar3Rpr>(g);
  // Two draw-wire gauges in the plane, from a point left of the robot and one below it to
  // the platform triangle's centroid: together they measure where that point is. Their
  // base points fix the base frame. Distances to one platform point cannot see a turn of the
  // platform frame about it: leg2.platform.y fixes that (with the gauges' platform point it
  // defines the platform frame). 14 free parameters.
  auto left = std::make_shared<LengthGauge>("gauge1", Vector3d(-200, 100, 0), Vector3d(20, 20, 0));
  auto below = std::make_shared<LengthGauge>("gauge2", Vector3d(150, -200, 0), Vector3d(20, 20, 0));
  auto model = std::make_shared<MeasurementModel>(
      robot, std::vector<std::shared_ptr<const Sensor>>{left, below});
  model->parameters().set_free("leg*", true);
  model->parameters().set_free("leg2.platform.y", false);
  return model;
}

}  // namespace

void register_planar_3rpr(ModelRegistry& registry) {
  registry.add_mechanism({"planar-3rpr",
                          "planar 3-RPR parallel robot: a platform moving in the plane z = 0 "
                          "(x, y, rotation about z) on three legs between base and platform "
                          "joints, actuators are leg lengths (mm)",
                          read_planar_3rpr, write_planar_3rpr});
  registry.add_preset(
      {"planar-3rpr",
       "the planar 3-RPR prototype of S. Schulz, 'On Using Inertial Measurement "
       "Units for Solving the Direct Kinematics Problem of Parallel Mechanisms', "
       "Robotics 8(4):99, 2019; two length gauges in the plane to one platform point",
       make_planar_3rpr});
}

}  // namespace kincal
