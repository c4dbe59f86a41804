#include "kincal/cli/urdf_io.hpp"

#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "kincal/models/point_tracker.hpp"
#include "kincal/models/pose_tracker.hpp"

namespace kincal::cli {

namespace {

constexpr double kMillimetresPerMetre = 1000.0;

Pose compose(const Pose& a, const Pose& b) {
  Pose c;
  c.rotation = a.rotation * b.rotation;
  c.translation = a.translation + a.rotation * b.translation;
  return c;
}

Pose inverse(const Pose& p) {
  Pose i;
  i.rotation = p.rotation.transpose();
  i.translation = -(i.rotation * p.translation);
  return i;
}

// A urdfdom pose (metres, quaternion) in kincal's units (mm).
Pose from_urdf(const urdf::Pose& p) {
  Pose out;
  out.rotation = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z)
                     .normalized()
                     .toRotationMatrix();
  out.translation = Vector3d(p.position.x, p.position.y, p.position.z) * kMillimetresPerMetre;
  return out;
}

std::string full(double v) {
  if (v == 0) v = 0;
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

urdf::ModelInterfaceSharedPtr parse(const std::string& text) {
  // urdfdom reports through console_bridge on stderr; the one-line error below says it all.
  console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE);
  urdf::ModelInterfaceSharedPtr model;
  try {
    model = urdf::parseURDF(text);
  } catch (const std::exception& e) {
    throw UrdfError(std::string("not a valid URDF (urdfdom: ") + e.what() + ")");
  }
  if (!model)
    throw UrdfError("not a valid URDF (urdfdom could not parse it; `check_urdf FILE` shows why)");
  return model;
}

// The joints from the root link down to `link`, root first.
std::vector<urdf::JointConstSharedPtr> joints_to(const urdf::ModelInterface& model,
                                                 const std::string& link) {
  std::vector<urdf::JointConstSharedPtr> chain;
  urdf::LinkConstSharedPtr at = model.getLink(link);
  while (at && at->parent_joint) {
    chain.push_back(at->parent_joint);
    at = model.getLink(at->parent_joint->parent_link_name);
  }
  std::reverse(chain.begin(), chain.end());
  return chain;
}

const char* joint_type_name(int type) {
  switch (type) {
    case urdf::Joint::REVOLUTE:
      return "revolute";
    case urdf::Joint::CONTINUOUS:
      return "continuous";
    case urdf::Joint::PRISMATIC:
      return "prismatic";
    case urdf::Joint::FIXED:
      return "fixed";
    case urdf::Joint::FLOATING:
      return "floating";
    case urdf::Joint::PLANAR:
      return "planar";
  }
  return "unknown";
}

// The fixed transform from the URDF's root link to `link` (mm); throws when a moving joint
// lies between them.
Pose root_to(const urdf::ModelInterface& model, const std::string& link) {
  Pose p;
  for (const auto& joint : joints_to(model, link)) {
    if (joint->type != urdf::Joint::FIXED)
      throw UrdfError("joint '" + joint->name + "' (" + joint_type_name(joint->type) +
                      ") between the URDF's root link '" + model.getRoot()->name +
                      "' and the base link '" + link +
                      "' moves: the world frame cannot be attached to the root; import with "
                      "--base at or above that joint");
    p = compose(p, from_urdf(joint->parent_to_joint_origin_transform));
  }
  return p;
}

}  // namespace

UrdfArmGeometry import_urdf(const std::string& text, const std::string& file,
                            const std::string& base_link, const std::string& tip_link) {
  const urdf::ModelInterfaceSharedPtr model = parse(text);
  UrdfArmGeometry g;
  g.urdf_file = file;
  g.urdf_text = text;
  g.base_link = base_link.empty() ? model->getRoot()->name : base_link;
  g.tip_link = tip_link;
  if (!model->getLink(g.base_link))
    throw UrdfError("no link '" + g.base_link + "' in the URDF (--base)");
  if (!model->getLink(tip_link)) throw UrdfError("no link '" + tip_link + "' in the URDF (--tip)");
  // The chain base -> tip: the tip's ancestors below the base.
  std::vector<urdf::JointConstSharedPtr> chain;
  for (urdf::LinkConstSharedPtr at = model->getLink(tip_link); at->name != g.base_link;) {
    if (!at->parent_joint)
      throw UrdfError("link '" + tip_link + "' (--tip) is not below link '" + g.base_link +
                      "' (--base) in the URDF's tree");
    chain.push_back(at->parent_joint);
    at = model->getLink(at->parent_joint->parent_link_name);
  }
  std::reverse(chain.begin(), chain.end());
  Pose pending;  // fixed joints not yet folded into a moving joint's origin
  for (const auto& joint : chain) {
    pending = compose(pending, from_urdf(joint->parent_to_joint_origin_transform));
    if (joint->type == urdf::Joint::FIXED) continue;
    if (joint->type != urdf::Joint::REVOLUTE && joint->type != urdf::Joint::CONTINUOUS &&
        joint->type != urdf::Joint::PRISMATIC)
      throw UrdfError("joint '" + joint->name + "' is " + joint_type_name(joint->type) +
                      "; expected revolute, continuous, prismatic or fixed joints between " +
                      "base and tip");
    if (joint->mimic)
      throw UrdfError("joint '" + joint->name +
                      "' mimics another joint; kincal needs every moving joint as an actuator");
    UrdfArmJoint j;
    j.name = joint->name;
    j.type = joint->type == urdf::Joint::REVOLUTE     ? UrdfJointType::kRevolute
             : joint->type == urdf::Joint::CONTINUOUS ? UrdfJointType::kContinuous
                                                      : UrdfJointType::kPrismatic;
    j.origin = frame_parameters(pending);
    pending = Pose{};
    j.axis = Vector3d(joint->axis.x, joint->axis.y, joint->axis.z);
    if (!(j.axis.norm() > 1e-9)) throw UrdfError("joint '" + joint->name + "' has a zero axis");
    j.axis.normalize();
    const double unit = j.type == UrdfJointType::kPrismatic ? kMillimetresPerMetre : 1.0;
    if (j.type == UrdfJointType::kContinuous) {
      j.lower = j.upper = NAN;
    } else {
      if (!joint->limits)
        throw UrdfError("joint '" + joint->name + "' has no <limit> (required for its type)");
      j.lower = joint->limits->lower * unit;
      j.upper = joint->limits->upper * unit;
      if (!(j.lower <= 0 && 0 <= j.upper)) j.home = 0.5 * (j.lower + j.upper);
    }
    if (j.name == "base" || j.name == "tool" ||
        j.name.find_first_of(", \t\r\n#\"*?.") != std::string::npos)
      throw UrdfError("joint name '" + j.name +
                      "' cannot name a measurement column and parameters (it must not be "
                      "'base' or 'tool' nor contain commas, spaces, '#', quotes, '*', '?' or "
                      "'.'); rename it in the URDF");
    g.joints.push_back(j);
  }
  if (g.joints.empty())
    throw UrdfError("no moving joint between link '" + g.base_link + "' and link '" + tip_link +
                    "'");
  g.tip = frame_parameters(pending);
  return g;
}

MeasuredFrames measured_frames(const MeasurementModel& model, const VectorXd& values) {
  MeasuredFrames out;
  int trackers = 0, sockets = 0;
  for (std::size_t k = 0; k < model.sensors().size(); ++k) {
    const Sensor& sensor = *model.sensors()[k];
    const auto p =
        values.segment(model.sensor_parameter_offset(static_cast<int>(k)), sensor.num_parameters());
    if (sensor.type() == "point-tracker") {
      out.world_from_mechanism =
          inverse(frame_from_parameters(p.segment<6>(PointTracker::kFrameIndex)));
      out.tcp_in_tool = Pose{};
      out.tcp_in_tool.translation = p.segment<3>(PointTracker::kTargetIndex);
    } else if (sensor.type() == "pose-tracker") {
      out.world_from_mechanism =
          inverse(frame_from_parameters(p.segment<6>(PoseTracker::kFrameIndex)));
      out.tcp_in_tool = frame_from_parameters(p.segment<6>(PoseTracker::kMarkerIndex));
    } else {
      sockets += sensor.type() == "socket";
      continue;
    }
    ++trackers;
    out.sensor = sensor.type() + " '" + sensor.name() + "'";
  }
  if (trackers == 0 && sockets > 0) {
    // A socket reads the tool point (the end frame's origin) in the mechanism's base
    // coordinates, where the sockets' centres were estimated: that frame is the measurement
    // frame, and the tool point the measured one.
    out.world_from_mechanism = Pose{};
    out.tcp_in_tool = Pose{};
    out.sensor = "the base frame of the arm, in which the centres of the sockets were estimated";
    return out;
  }
  if (trackers == 1 && sockets > 0)
    throw UrdfError(
        "the model has a tracker and sockets, which measure different points of the tool, so "
        "the measured point (tcp) is not defined; export a model with one tracker or with "
        "sockets");
  if (trackers != 1)
    throw UrdfError(
        std::string(trackers == 0 ? "the model has no point or pose tracker and no socket"
                                  : "the model has several point or pose trackers") +
        ", so the measured point (tcp) and the measurement frame (world) are not defined; "
        "export a model with exactly one tracker, or with sockets");
  return out;
}

std::string export_urdf_arm(const MeasurementModel& model, const VectorXd& values,
                            const std::string& header) {
  const auto* arm = dynamic_cast<const UrdfArm*>(&model.mechanism());
  if (!arm) throw UrdfError("not a urdf-arm model");
  const UrdfArmGeometry g =
      arm->geometry_from(values.head(static_cast<int>(arm->parameters().size())));
  if (g.urdf_text.empty())
    throw UrdfError(
        "the model keeps no URDF text (mechanism.urdf.text) to write the corrections into; "
        "re-import the robot with kincal model --urdf");
  // The model's nominal chain must be the one its URDF text describes, or the corrections
  // would be written onto other origins than they were fitted for.
  const UrdfArmGeometry text_geometry = import_urdf(g.urdf_text, "", g.base_link, g.tip_link);
  bool same = text_geometry.joints.size() == g.joints.size();
  std::string differs;
  for (std::size_t i = 0; same && i < g.joints.size(); ++i) {
    const UrdfArmJoint &a = g.joints[i], &b = text_geometry.joints[i];
    const Pose pa = frame_from_parameters(a.origin), pb = frame_from_parameters(b.origin);
    if (a.name != b.name || a.type != b.type || (a.axis - b.axis).norm() > 1e-9 ||
        (pa.translation - pb.translation).norm() > 1e-9 ||
        (pa.rotation - pb.rotation).norm() > 1e-9) {
      same = false;
      differs = "joint '" + a.name + "'";
    }
  }
  if (same) {
    const Pose ta = frame_from_parameters(g.tip), tb = frame_from_parameters(text_geometry.tip);
    if ((ta.translation - tb.translation).norm() > 1e-9 ||
        (ta.rotation - tb.rotation).norm() > 1e-9)
      same = false, differs = "the tip";
  }
  if (!same)
    throw UrdfError("the model's nominal chain differs from its URDF text (" +
                    (differs.empty() ? std::string("number of joints") : differs) +
                    "): the model file was edited after import; re-import the URDF");

  const urdf::ModelInterfaceSharedPtr urdf_model = parse(g.urdf_text);
  const std::string root = urdf_model->getRoot()->name;
  // A URDF whose root is already `world` keeps it, as the measurement frame; anywhere else
  // the name is taken.
  const bool root_is_world = root == "world";
  if (urdf_model->getLink("world") && !root_is_world)
    throw UrdfError(
        "the URDF has a link 'world' that is not its root; the export adds `world` as the "
        "measurement frame at the root: rename that link in the URDF and re-import");
  if (urdf_model->getLink("tcp"))
    throw UrdfError(
        "the URDF already has a link 'tcp', which the export adds (the measured point); "
        "rename it in the URDF and re-import");
  const Pose root_from_base = root_to(*urdf_model, g.base_link);
  const MeasuredFrames frames = measured_frames(model, values);
  const Pose world_from_root = compose(
      compose(frames.world_from_mechanism, frame_from_parameters(g.base)), inverse(root_from_base));
  const Pose tcp = compose(frame_from_parameters(g.tool), frames.tcp_in_tool);

  TiXmlDocument doc;
  doc.Parse(g.urdf_text.c_str());
  if (doc.Error()) throw UrdfError(std::string("the URDF text is not XML: ") + doc.ErrorDesc());
  TiXmlElement* robot = doc.RootElement();
  if (!robot || std::string(robot->Value()) != "robot")
    throw UrdfError("the URDF's root element is not <robot>");
  auto set_origin = [](TiXmlElement* element, const Pose& pose) {
    TiXmlElement* origin = element->FirstChildElement("origin");
    if (!origin) {
      TiXmlElement fresh("origin");
      TiXmlNode* first = element->FirstChild();
      origin = (first ? element->InsertBeforeChild(first, fresh) : element->InsertEndChild(fresh))
                   ->ToElement();
    }
    const Vector6d f = frame_parameters(pose);
    origin->SetAttribute("xyz", full(f[0] / kMillimetresPerMetre) + " " +
                                    full(f[1] / kMillimetresPerMetre) + " " +
                                    full(f[2] / kMillimetresPerMetre));
    origin->SetAttribute("rpy", full(f[3]) + " " + full(f[4]) + " " + full(f[5]));
  };
  // The origins to write, by joint name: the chain's corrected, and with a root `world`,
  // every joint from it moved by where the root is in the measurement frame.
  std::map<std::string, Pose> origins;
  for (const UrdfArmJoint& joint : g.joints) {
    const Pose urdf_origin =
        from_urdf(urdf_model->getJoint(joint.name)->parent_to_joint_origin_transform);
    origins[joint.name] = compose(compose(urdf_origin, frame_from_parameters(joint.origin_error)),
                                  urdf_joint_motion(joint, joint.offset));
  }
  if (root_is_world)
    for (const auto& [name, joint] : urdf_model->joints_)
      if (joint->parent_link_name == "world")
        origins[name] =
            compose(world_from_root, origins.count(name)
                                         ? origins[name]
                                         : from_urdf(joint->parent_to_joint_origin_transform));
  for (const auto& [name, pose] : origins) {
    TiXmlElement* element = robot->FirstChildElement("joint");
    while (element && (element->Attribute("name") == nullptr ||
                       std::string(element->Attribute("name")) != name))
      element = element->NextSiblingElement("joint");
    if (!element) throw UrdfError("joint '" + name + "' not found in the URDF text");
    set_origin(element, pose);
  }
  auto unique_joint_name = [&](std::string name) {
    while (urdf_model->getJoint(name)) name += "_";
    return name;
  };
  TiXmlElement world("link");
  world.SetAttribute("name", "world");
  TiXmlElement world_joint("joint");
  world_joint.SetAttribute("name", unique_joint_name("world_to_" + root));
  world_joint.SetAttribute("type", "fixed");
  TiXmlElement tcp_link("link");
  tcp_link.SetAttribute("name", "tcp");
  TiXmlElement tcp_joint("joint");
  tcp_joint.SetAttribute("name", unique_joint_name(g.tip_link + "_to_tcp"));
  tcp_joint.SetAttribute("type", "fixed");
  auto add_link_refs = [](TiXmlElement& joint, const std::string& parent,
                          const std::string& child) {
    TiXmlElement p("parent"), c("child");
    p.SetAttribute("link", parent);
    c.SetAttribute("link", child);
    joint.InsertEndChild(p);
    joint.InsertEndChild(c);
  };
  add_link_refs(world_joint, "world", root);
  add_link_refs(tcp_joint, g.tip_link, "tcp");
  set_origin(&world_joint, world_from_root);
  set_origin(&tcp_joint, tcp);
  if (root_is_world) {
    robot->InsertEndChild(
        TiXmlComment((" kincal: the root link world is the measurement frame (" + frames.sensor +
                      "): the joints from it carry the calibrated base ")
                         .c_str()));
  } else {
    robot->InsertEndChild(TiXmlComment(
        (" kincal: the measurement frame (" + frames.sensor + ") and the calibrated base ")
            .c_str()));
    robot->InsertEndChild(world);
    robot->InsertEndChild(world_joint);
  }
  robot->InsertEndChild(
      TiXmlComment(" kincal: the measured point or frame (tool frame, and a tracker's target) "));
  robot->InsertEndChild(tcp_link);
  robot->InsertEndChild(tcp_joint);
  // The header goes first in the document, after the XML declaration.
  TiXmlComment comment(header.c_str());
  TiXmlNode* first = doc.FirstChild();
  if (first && first->ToDeclaration())
    doc.InsertAfterChild(first, comment);
  else if (first)
    doc.InsertBeforeChild(first, comment);
  TiXmlPrinter printer;
  printer.SetIndent("  ");
  doc.Accept(&printer);
  return printer.Str();
}

}  // namespace kincal::cli
