// The URDF arm in model files (written by `kincal model --urdf`; models/urdf_arm.hpp):
//
//   "mechanism": {
//     "type": "urdf-arm",
//     "urdf": { "file": "ur5.urdf", "text": "<robot ...>...</robot>" },
//                                       the robot description it was imported from, re-emitted
//                                       by `kincal export --format urdf` with the corrections
//     "base_link": "base_link", "tip_link": "flange",
//     "base": { "position": [x, y, z], "rotation_zyx_deg": [rx, ry, rz] },  optional, identity:
//                                       the base link in the measurement frame
//     "joints": [                       the moving joints from base to tip
//       { "name": "shoulder_pan_joint", URDF joint name = actuator column = parameter prefix
//         "type": "revolute",           "revolute", "continuous" (rad) or "prismatic" (mm)
//         "origin": { "position": [..] (mm), "rotation_zyx_deg": [r, p, y] },
//                                       the URDF origin (fixed joints before it folded in)
//         "axis": [0, 0, 1],            unit axis in the joint frame
//         "lower_deg": -360, "upper_deg": 360,   URDF limits ("lower"/"upper" in mm for a
//                                       prismatic joint; none for a continuous one)
//         "home_deg": 0,                optional, default 0 ("home", mm, prismatic)
//         "range_deg": 28.6,            optional: half-width of the default configuration box
//         "origin_error": { "position": [..], "rotation_zyx_deg": [..] },  optional, zero
//         "offset_deg": 0               optional, zero ("offset", mm, prismatic)
//       }, ... ],
//     "tip": { "position": ..., "rotation_zyx_deg": ... },  optional, identity: fixed joints
//                                       from the last moving joint's child link to the tip
//     "tool": { ... }                   optional, identity: the tool frame on the tip link
//     "compliance": { ... }             optional, none: joint compliance under gravity
//                                       (models/joint_compliance_file.hpp)
//   }

#include <cmath>
#include <set>

#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/models/joint_compliance_file.hpp"
#include "kincal/models/urdf_arm.hpp"

namespace kincal {

namespace {

using namespace json_field;

double clean(double v) { return v + 0.0; }

UrdfArmJoint read_joint(const Json& j, const JsonPath& at) {
  object(j, at);
  UrdfArmJoint joint;
  joint.name = name(member(j, "name", at), at / "name");
  const std::string type = string(member(j, "type", at), at / "type");
  if (type == "revolute")
    joint.type = UrdfJointType::kRevolute;
  else if (type == "continuous")
    joint.type = UrdfJointType::kContinuous;
  else if (type == "prismatic")
    joint.type = UrdfJointType::kPrismatic;
  else
    (at / "type")
        .fail("expected \"revolute\", \"continuous\" or \"prismatic\", got \"" +
              message_excerpt(type) + "\"");
  const bool prismatic = joint.type == UrdfJointType::kPrismatic;
  const bool limited = joint.type != UrdfJointType::kContinuous;
  const std::string suffix = prismatic ? "" : "_deg";
  const double unit = prismatic ? 1.0 : kRadiansPerDegree;
  std::set<std::string> allowed = {"name", "type", "origin", "axis", "origin_error"};
  for (const char* key : {"home", "range", "offset"}) allowed.insert(key + suffix);
  if (limited)
    for (const char* key : {"lower", "upper"}) allowed.insert(key + suffix);
  for (const char* key : {"home", "range", "offset", "lower", "upper"}) {
    const std::string other = prismatic ? std::string(key) + "_deg" : std::string(key);
    if (j.contains(other))
      (at / other)
          .fail(prismatic
                    ? "a prismatic joint moves in mm: expected \"" + std::string(key) + "\""
                    : "a " + type + " joint's angles are in degrees: expected " + key + "_deg");
  }
  check_keys(j, at, allowed);
  joint.origin = frame(member(j, "origin", at), at / "origin");
  joint.axis = vector3(member(j, "axis", at), at / "axis");
  if (!(joint.axis.norm() > 1e-9)) (at / "axis").fail("expected a non-zero axis");
  if (const Json* e = optional(j, "origin_error"))
    joint.origin_error = frame(*e, at / "origin_error");
  joint.offset = number_or(j, "offset" + suffix, 0.0, at) * unit;
  joint.home = number_or(j, "home" + suffix, 0.0, at) * unit;
  if (limited) {
    joint.lower = number(member(j, "lower" + suffix, at), at / ("lower" + suffix)) * unit;
    joint.upper = number(member(j, "upper" + suffix, at), at / ("upper" + suffix)) * unit;
    if (!(joint.lower <= joint.upper)) (at / ("upper" + suffix)).fail("expected upper >= lower");
  } else {
    joint.lower = joint.upper = NAN;
  }
  if (const Json* r = optional(j, "range" + suffix)) {
    const double range = number(*r, at / ("range" + suffix));
    if (!(range > 0)) (at / ("range" + suffix)).fail("expected a half-width > 0");
    joint.range = range * unit;
  }
  return joint;
}

std::shared_ptr<const Mechanism> read_urdf_arm(const Json& j, const JsonPath& where) {
  check_keys(
      j, where,
      {"type", "urdf", "base_link", "tip_link", "base", "joints", "tip", "tool", "compliance"});
  UrdfArmGeometry g;
  if (const Json* u = optional(j, "urdf")) {
    const JsonPath at = where / "urdf";
    object(*u, at);
    check_keys(*u, at, {"file", "text"});
    if (const Json* f = optional(*u, "file")) g.urdf_file = string(*f, at / "file");
    if (const Json* t = optional(*u, "text")) g.urdf_text = string(*t, at / "text");
  }
  g.base_link = name(member(j, "base_link", where), where / "base_link");
  g.tip_link = name(member(j, "tip_link", where), where / "tip_link");
  if (const Json* base = optional(j, "base")) g.base = frame(*base, where / "base");
  if (const Json* tip = optional(j, "tip")) g.tip = frame(*tip, where / "tip");
  if (const Json* tool = optional(j, "tool")) g.tool = frame(*tool, where / "tool");
  const Json& joints = member(j, "joints", where);
  if (!joints.is_array() || joints.empty())
    (where / "joints").fail("expected a non-empty array of joint objects");
  std::set<std::string> names;
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const JsonPath at = (where / "joints")[i];
    UrdfArmJoint joint = read_joint(joints[i], at);
    if (joint.name == "base" || joint.name == "tool")
      (at / "name").fail("'" + joint.name + "' names the arm's " + joint.name + " frame");
    if (!names.insert(joint.name).second)
      (at / "name").fail("'" + joint.name + "' is the name of an earlier joint");
    g.joints.push_back(joint);
  }
  if (const Json* c = optional(j, "compliance"))
    g.compliance = read_compliance(*c, where / "compliance", g.joints.size());
  try {
    return std::make_shared<UrdfArm>(std::move(g));
  } catch (const std::invalid_argument& e) {
    where.fail(e.what());
  }
}

Json write_urdf_arm(const Mechanism& mechanism, const Eigen::Ref<const VectorXd>& values) {
  const auto& arm = dynamic_cast<const UrdfArm&>(mechanism);
  const UrdfArmGeometry g = arm.geometry_from(values);
  auto frame_json = [](const Vector6d& f) { return pose_json(f.head<3>(), f.tail<3>()); };
  Json out;
  Json urdf = Json::object();
  if (!g.urdf_file.empty()) urdf["file"] = g.urdf_file;
  if (!g.urdf_text.empty()) urdf["text"] = g.urdf_text;
  out["urdf"] = urdf;
  out["base_link"] = g.base_link;
  out["tip_link"] = g.tip_link;
  out["base"] = frame_json(g.base);
  out["joints"] = Json::array();
  for (const UrdfArmJoint& joint : g.joints) {
    const bool prismatic = joint.type == UrdfJointType::kPrismatic;
    const std::string suffix = prismatic ? "" : "_deg";
    const double unit = prismatic ? 1.0 : kRadiansPerDegree;
    Json j = {{"name", joint.name},
              {"type", to_string(joint.type)},
              {"origin", frame_json(joint.origin)},
              {"axis", array3(joint.axis)}};
    if (joint.type != UrdfJointType::kContinuous) {
      j["lower" + suffix] = clean(joint.lower / unit);
      j["upper" + suffix] = clean(joint.upper / unit);
    }
    j["home" + suffix] = clean(joint.home / unit);
    const double default_range =
        prismatic ? UrdfArm::kDefaultPrismaticRange : UrdfArm::kDefaultRevoluteRange;
    if (joint.range != default_range) j["range" + suffix] = joint.range / unit;
    j["origin_error"] = frame_json(joint.origin_error);
    j["offset" + suffix] = clean(joint.offset / unit);
    out["joints"].push_back(j);
  }
  out["tip"] = frame_json(g.tip);
  out["tool"] = frame_json(g.tool);
  if (g.compliance.enabled) out["compliance"] = compliance_json(g.compliance);
  return out;
}

}  // namespace

void register_urdf_arm(ModelRegistry& registry) {
  registry.add_mechanism({"urdf-arm",
                          "serial arm imported from a URDF (kincal model --urdf): the URDF's "
                          "joint origins and axes, a 6-DOF origin error and an offset per "
                          "moving joint, base and tool frames; exported back into the user's "
                          "own URDF",
                          read_urdf_arm, write_urdf_arm});
  registry.add_preset({"ur5-urdf", ur5_urdf_description(), make_ur5_urdf});
  registry.add_preset(
      {"ur5-urdf-compliance", ur5_urdf_compliance_description(), make_ur5_urdf_compliance});
}

}  // namespace kincal
