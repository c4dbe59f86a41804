// The serial arm in model files, and its presets.
//
//   "mechanism": {
//     "type": "serial-arm",
//     "base": { "position": [x, y, z], "rotation_zyx_deg": [rx, ry, rz] },  optional, identity
//     "joints": [                                  one or more, from the base to the tool
//       { "name": "joint1",                        optional, default "joint<i>" (1-based);
//                                                  actuator column and parameter prefix
//         "type": "revolute",                      optional: "revolute" (default, rad) or
//                                                  "prismatic" (mm)
//         "convention": "dh",                      optional: "dh" (default) or "hayati"
//                                                  (revolute joints only)
//         "a": 0,                                  mm
//         "alpha_deg": 90,
//         "d": 0,                                  mm; "dh" only (a prismatic joint's offset)
//         "beta_deg": 0,                           "hayati" only, replaces d
//         "theta_deg": 0,                          a revolute joint's offset
//         "home_deg": 0,                           optional, default 0: the joint at home;
//                                                  "home" (mm) for a prismatic joint
//         "range_deg": 28.6                        optional, > 0: half-width of the default
//                                                  configuration box around home ("range",
//                                                  mm, for a prismatic joint); default
//                                                  0.5 rad / 50 mm
//       }, ... ],
//     "tool": { "position": [x, y, z], "rotation_zyx_deg": [rx, ry, rz] }   optional, identity
//     "compliance": { ... }   optional, none: joint compliance under gravity, centres of mass
//                             in DH frame i (models/joint_compliance_file.hpp)
//   }
// Link i is Rz(theta + q) Tz(d) Tx(a) Rx(alpha) ("dh") or Rz(theta + q) Tx(a) Rx(alpha)
// Ry(beta) ("hayati"); see models/serial_arm.hpp.

#include <cmath>
#include <set>

#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/models/joint_compliance_file.hpp"
#include "kincal/models/serial_arm.hpp"
#include "kincal/models/serial_arm_presets.hpp"

namespace kincal {

namespace {

using namespace json_field;

SerialJoint read_joint(const Json& j, const JsonPath& at, int index) {
  if (!j.is_object())
    at.fail("expected a joint object with a, alpha_deg, d or beta_deg, theta_deg");
  SerialJoint joint;
  joint.name = "joint" + std::to_string(index + 1);
  if (const Json* n = optional(j, "name")) joint.name = name(*n, at / "name");
  if (const Json* t = optional(j, "type")) {
    const std::string type = string(*t, at / "type");
    if (type == "prismatic")
      joint.type = JointType::kPrismatic;
    else if (type != "revolute")
      (at / "type")
          .fail("expected \"revolute\" or \"prismatic\", got \"" + message_excerpt(type) + "\"");
  }
  const bool revolute = joint.type == JointType::kRevolute;
  if (const Json* c = optional(j, "convention")) {
    const std::string convention = string(*c, at / "convention");
    if (convention == "hayati")
      joint.convention = LinkConvention::kHayati;
    else if (convention != "dh")
      (at / "convention")
          .fail("expected \"dh\" or \"hayati\", got \"" + message_excerpt(convention) + "\"");
    if (!revolute && joint.convention == LinkConvention::kHayati)
      (at / "convention")
          .fail(
              "expected \"dh\" for a prismatic joint (its variable is d, which Hayati's "
              "convention replaces by beta)");
  }
  const bool dh = joint.convention == LinkConvention::kDh;
  // Say why a key of the other convention or joint type is wrong, not only that it is.
  if (!dh && j.contains("d"))
    (at / "d").fail("a Hayati link has no d (beta_deg replaces it); expected beta_deg");
  if (dh && j.contains("beta_deg"))
    (at / "beta_deg").fail("a DH link has no beta; expected d, or convention \"hayati\"");
  for (const char* key : {"home", "range"})
    if (revolute && j.contains(key))
      (at / key).fail(std::string("a revolute joint's angles are in degrees: expected ") + key +
                      "_deg");
  for (const char* key : {"home_deg", "range_deg"})
    if (!revolute && j.contains(key))
      (at / key).fail(std::string("a prismatic joint moves in mm: expected \"") +
                      std::string(key).substr(0, std::string(key).size() - 4) + "\"");
  std::set<std::string> allowed = {"name", "type", "convention", "a", "alpha_deg", "theta_deg"};
  allowed.insert(dh ? "d" : "beta_deg");
  allowed.insert(revolute ? "home_deg" : "home");
  allowed.insert(revolute ? "range_deg" : "range");
  check_keys(j, at, allowed);

  joint.a = number(member(j, "a", at), at / "a");
  joint.alpha = radians_from_degrees(number(member(j, "alpha_deg", at), at / "alpha_deg"));
  if (dh)
    joint.d = number(member(j, "d", at), at / "d");
  else
    joint.beta = radians_from_degrees(number(member(j, "beta_deg", at), at / "beta_deg"));
  joint.theta = radians_from_degrees(number(member(j, "theta_deg", at), at / "theta_deg"));
  const double unit = revolute ? kRadiansPerDegree : 1.0;
  const std::string home_key = revolute ? "home_deg" : "home";
  const std::string range_key = revolute ? "range_deg" : "range";
  joint.home = number_or(j, home_key, 0.0, at) * unit;
  if (const Json* r = optional(j, range_key)) {
    const double range = number(*r, at / range_key);
    if (!(range > 0)) (at / range_key).fail("expected a half-width > 0");
    joint.range = range * unit;
  }
  return joint;
}

std::shared_ptr<const Mechanism> read_serial_arm(const Json& j, const JsonPath& where) {
  check_keys(j, where, {"type", "base", "joints", "tool", "compliance"});
  SerialArmGeometry g;
  if (const Json* base = optional(j, "base")) g.base = frame(*base, where / "base");
  if (const Json* tool = optional(j, "tool")) g.tool = frame(*tool, where / "tool");
  const Json& joints = member(j, "joints", where);
  if (!joints.is_array() || joints.empty())
    (where / "joints").fail("expected a non-empty array of joint objects");
  std::set<std::string> names;
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const JsonPath at = (where / "joints")[i];
    SerialJoint joint = read_joint(joints[i], at, static_cast<int>(i));
    if (joint.name == "base" || joint.name == "tool")
      (at / "name")
          .fail("'" + joint.name + "' names the arm's " + joint.name +
                " frame; expected another joint name");
    if (!names.insert(joint.name).second)
      (at / "name")
          .fail("'" + joint.name +
                "' is the name of an earlier joint; expected unique "
                "joint names");
    g.joints.push_back(joint);
  }
  if (const Json* c = optional(j, "compliance"))
    g.compliance = read_compliance(*c, where / "compliance", g.joints.size());
  try {
    return std::make_shared<SerialArm>(std::move(g));
  } catch (const std::invalid_argument& e) {
    where.fail(e.what());
  }
}

// "+ 0.0" turns -0 into 0 so that files do not show "-0.0".
double clean(double v) { return v + 0.0; }
double link_degrees(double radians) {
  return clean(degrees_reading_back(radians, radians / kRadiansPerDegree, radians_from_degrees));
}

Json write_serial_arm(const Mechanism& mechanism, const Eigen::Ref<const VectorXd>& values) {
  const auto& arm = dynamic_cast<const SerialArm&>(mechanism);
  const auto base = values.segment<6>(SerialArm::base_index());
  const auto tool = values.segment<6>(arm.tool_index());
  Json out;
  out["base"] = pose_json(base.head<3>(), base.tail<3>());
  out["joints"] = Json::array();
  for (int i = 0; i < arm.num_joints(); ++i) {
    const SerialJoint& joint = arm.nominal_geometry().joints[i];
    const auto link = values.segment<4>(SerialArm::joint_index(i));
    const bool revolute = joint.type == JointType::kRevolute;
    const bool dh = joint.convention == LinkConvention::kDh;
    Json j = {{"name", joint.name},
              {"type", to_string(joint.type)},
              {"convention", to_string(joint.convention)},
              {"a", clean(link[SerialArm::kA])},
              {"alpha_deg", link_degrees(link[SerialArm::kAlpha])}};
    if (dh)
      j["d"] = clean(link[SerialArm::kDOrBeta]);
    else
      j["beta_deg"] = link_degrees(link[SerialArm::kDOrBeta]);
    j["theta_deg"] = link_degrees(link[SerialArm::kTheta]);
    const double unit = revolute ? kRadiansPerDegree : 1.0;
    j[revolute ? "home_deg" : "home"] = clean(joint.home / unit);
    const double default_range =
        revolute ? SerialArm::kDefaultRevoluteRange : SerialArm::kDefaultPrismaticRange;
    if (joint.range != default_range) j[revolute ? "range_deg" : "range"] = joint.range / unit;
    out["joints"].push_back(j);
  }
  out["tool"] = pose_json(tool.head<3>(), tool.tail<3>());
  if (arm.has_compliance())
    out["compliance"] = compliance_json(arm.geometry_from(values).compliance);
  return out;
}

}  // namespace

void register_serial_arm(ModelRegistry& registry) {
  registry.add_mechanism({"serial-arm",
                          "serial arm of revolute (rad) and prismatic (mm) joints: standard DH "
                          "links, Hayati links where consecutive axes are parallel, joint "
                          "offsets, base and tool frames",
                          read_serial_arm, write_serial_arm});
  registry.add_preset({"puma560", puma560_description(), make_puma560});
  registry.add_preset({"ur5", ur5_description(), make_ur5});
}

}  // namespace kincal
