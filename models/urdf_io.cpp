#include "kincal/models/urdf_io.hpp"

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>

#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/io/json_input.hpp"
#include "kincal/framework/kinematics/names.hpp"
#include "kincal/models/model_io.hpp"
#include "kincal/models/point_tracker.hpp"
#include "kincal/models/pose_tracker.hpp"

namespace kincal {

namespace {

constexpr double kMillimetresPerMetre = 1000.0;

// A urdfdom pose (metres, quaternion) in kincal's units (mm).
Pose from_urdf(const urdf::Pose& p) {
  Pose out;
  out.rotation = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z)
                     .normalized()
                     .toRotationMatrix();
  out.translation = Vector3d(p.position.x, p.position.y, p.position.z) * kMillimetresPerMetre;
  return out;
}

// The shortest decimal that reads back as `v`: an origin the calibration left as it was
// keeps the user's "0.1" rather than becoming "0.10000000000000001".
std::string full(double v) {
  if (v == 0) v = 0;
  char buf[40];
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

// urdfdom's model of a URDF, and the XML it was read from (the lines of its elements, the
// places the export edits).
struct ReadUrdf {
  XmlText xml;
  urdf::ModelInterfaceSharedPtr model;
};

// "line N: <joint name="j">" for the element `kind` named `name` under the root.
std::string element_at(const std::string& text, const XmlText& xml, const char* kind,
                       const std::string& name) {
  const std::string element = std::string("<") + kind + " name=\"" + message_excerpt(name) + "\">";
  const int i = xml.child(xml.root, kind, "name", name);
  if (i < 0) return element;
  return "line " + std::to_string(line_at(text, xml.elements[static_cast<std::size_t>(i)].begin)) +
         ": " + element;
}

urdf::ModelInterfaceSharedPtr parse_with_urdfdom(const std::string& text) {
  // urdfdom reports through console_bridge on stderr; the one-line error below says it all.
  console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE);
  // TinyXML decodes a character reference (&#xE9;) to UTF-8 only in a document it knows to be
  // UTF-8, which a byte order mark tells it; without one it writes the single byte 0xE9. The
  // text is UTF-8 (scan_urdf_xml checked), so say so.
  const char* kBom = "\xEF\xBB\xBF";
  const std::string utf8 = text.rfind(kBom, 0) == 0 ? text : kBom + text;
  urdf::ModelInterfaceSharedPtr model;
  try {
    model = urdf::parseURDF(utf8);
  } catch (const std::exception& e) {
    throw UrdfError("not a valid URDF (urdfdom: " + message_excerpt(e.what(), 300) + ")");
  }
  if (!model)
    throw UrdfError("not a valid URDF (urdfdom could not parse it; `check_urdf FILE` shows why)");
  return model;
}

// urdfdom gives a link one parent joint, the last of several in name order, follows a cycle
// of joints as if it were a chain, and leaks the links of a cycle (they hold one another by
// shared_ptr) when it stops on a later error: kincal refuses both from the XML, before
// urdfdom. The joints are read as urdfdom reads them: <joint name> children of the root, the
// link attributes of their first <parent> and <child>; a joint without them is urdfdom's to
// refuse.
void check_tree(const std::string& text, const XmlText& xml) {
  struct Joint {
    std::string name, parent;
    std::size_t begin;
  };
  std::map<std::string, Joint> parent_joint;  // link -> the joint whose child it is
  auto link_of = [&](int joint, const char* end) -> const XmlAttribute* {
    const int e = xml.child(joint, end);
    return e < 0 ? nullptr : xml.elements[static_cast<std::size_t>(e)].attribute("link");
  };
  auto joint_at = [&](const Joint& j) {
    return "line " + std::to_string(line_at(text, j.begin)) + ": <joint name=\"" +
           message_excerpt(j.name) + "\">";
  };
  for (std::size_t i = 0; i < xml.elements.size(); ++i) {
    const XmlElement& e = xml.elements[i];
    if (e.parent != xml.root || e.name != "joint") continue;
    const XmlAttribute* name = e.attribute("name");
    const XmlAttribute* parent = link_of(static_cast<int>(i), "parent");
    const XmlAttribute* child = link_of(static_cast<int>(i), "child");
    if (!name || !parent || !child) continue;
    const Joint joint{name->value, parent->value, e.begin};
    const auto [at, inserted] = parent_joint.emplace(child->value, joint);
    if (!inserted)
      throw UrdfError(element_at(text, xml, "link", child->value) +
                      " is the child of two joints, " + joint_at(at->second) + " and " +
                      joint_at(joint) +
                      ": a URDF is a tree (one parent joint per link), and urdfdom would keep "
                      "one of the two silently");
  }
  // Every link has at most one parent now: follow the parents from each link, marking the
  // links of this walk, until a root or a link an earlier walk reached.
  std::map<std::string, int> walk_of;
  int walk = 0;
  for (const auto& start : parent_joint) {
    ++walk;
    for (std::string at = start.first;;) {
      const auto seen = walk_of.find(at);
      if (seen != walk_of.end()) {
        if (seen->second == walk)
          throw UrdfError(element_at(text, xml, "link", at) + " is its own ancestor: its parent " +
                          joint_at(parent_joint.at(at)) +
                          " closes a cycle of joints, and a URDF is a tree");
        break;
      }
      walk_of.emplace(at, walk);
      const auto parent = parent_joint.find(at);
      if (parent == parent_joint.end()) break;
      at = parent->second.parent;
    }
  }
}

ReadUrdf read_urdf(const std::string& text) {
  ReadUrdf r;
  r.xml = scan_urdf_xml(text);
  check_tree(text, r.xml);
  r.model = parse_with_urdfdom(text);
  return r;
}

// The joints from the root link down to `link`, root first (the tree is checked).
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
      throw UrdfError("joint '" + message_excerpt(joint->name) + "' (" +
                      joint_type_name(joint->type) + ") between the URDF's root link '" +
                      message_excerpt(model.getRoot()->name) + "' and the base link '" +
                      message_excerpt(link) +
                      "' moves: the world frame cannot be attached to the root; import with "
                      "--base at or above that joint");
    p = compose(p, from_urdf(joint->parent_to_joint_origin_transform));
  }
  return p;
}

// A name kincal takes from the URDF into the model file follows the names policy
// (framework/kinematics/names.hpp), as the model file's reader will check.
void check_name(const std::string& text, const XmlText& xml, const char* kind,
                const std::string& name, const std::string& role) {
  std::string problem = name_problem(name);
  if (problem.empty() && (name == "base" || name == "tool") && std::string(kind) == "joint")
    problem = "names the arm's " + name + " frame";
  if (problem.empty()) return;
  throw UrdfError(element_at(text, xml, kind, name) + ": the name " + problem + "; kincal " + role +
                  ": rename it in the URDF");
}

// The mass every link of the subtree at `link` adds to a chain segment (the links rigidly
// fixed to a moving joint's child link, and the branches off the chain with their own moving
// joints at zero), first moment in the segment's frame; `stop` is the chain's next moving
// joint, whose subtree is the next segment's.
void add_subtree_mass(const urdf::ModelInterface& model, const urdf::LinkConstSharedPtr& link,
                      const Pose& in_segment, const urdf::JointConstSharedPtr& stop, double& mass,
                      Vector3d& moment) {
  if (link->inertial && link->inertial->mass > 0) {
    const Vector3d centre = compose(in_segment, from_urdf(link->inertial->origin)).translation;
    mass += link->inertial->mass;
    moment += link->inertial->mass * centre;
  }
  for (const auto& joint : link->child_joints) {
    if (joint == stop) continue;
    const urdf::LinkConstSharedPtr child = model.getLink(joint->child_link_name);
    if (child)
      add_subtree_mass(model, child,
                       compose(in_segment, from_urdf(joint->parent_to_joint_origin_transform)),
                       stop, mass, moment);
  }
}

// The URDF's inertials as the masses each moving joint of `chain` carries (its child link's
// frame): empty when the URDF has none along or beyond the chain.
std::vector<PointMass> chain_masses(const urdf::ModelInterface& model,
                                    const std::vector<urdf::JointConstSharedPtr>& chain) {
  std::vector<urdf::JointConstSharedPtr> moving;
  for (const auto& joint : chain)
    if (joint->type != urdf::Joint::FIXED) moving.push_back(joint);
  std::vector<PointMass> out;
  double total = 0;
  for (std::size_t i = 0; i < moving.size(); ++i) {
    const urdf::JointConstSharedPtr stop = i + 1 < moving.size() ? moving[i + 1] : nullptr;
    double mass = 0;
    Vector3d moment = Vector3d::Zero();
    add_subtree_mass(model, model.getLink(moving[i]->child_link_name), Pose{}, stop, mass, moment);
    PointMass m;
    m.mass = mass;
    if (mass > 0) m.centre = moment / mass;
    total += mass;
    out.push_back(m);
  }
  if (!(total > 0)) out.clear();
  return out;
}

UrdfArmGeometry import_read(const ReadUrdf& r, const std::string& text, const std::string& file,
                            const std::string& base_link, const std::string& tip_link) {
  const urdf::ModelInterfaceSharedPtr& model = r.model;
  UrdfArmGeometry g;
  g.urdf_file = file;
  g.urdf_text = text;
  g.base_link = base_link.empty() ? model->getRoot()->name : base_link;
  g.tip_link = tip_link;
  if (!model->getLink(g.base_link))
    throw UrdfError("no link '" + message_excerpt(g.base_link) + "' in the URDF (--base)");
  if (!model->getLink(tip_link))
    throw UrdfError("no link '" + message_excerpt(tip_link) + "' in the URDF (--tip)");
  const std::string recorded = "records the base and tip links in the model file";
  check_name(text, r.xml, "link", g.base_link, recorded);
  check_name(text, r.xml, "link", g.tip_link, recorded);
  // The chain base -> tip: the tip's ancestors below the base.
  std::vector<urdf::JointConstSharedPtr> chain;
  for (urdf::LinkConstSharedPtr at = model->getLink(tip_link); at->name != g.base_link;) {
    if (!at->parent_joint)
      throw UrdfError("link '" + message_excerpt(tip_link) + "' (--tip) is not below link '" +
                      message_excerpt(g.base_link) + "' (--base) in the URDF's tree");
    chain.push_back(at->parent_joint);
    at = model->getLink(at->parent_joint->parent_link_name);
  }
  std::reverse(chain.begin(), chain.end());
  Pose pending;  // fixed joints not yet folded into a moving joint's origin
  for (const auto& joint : chain) {
    pending = compose(pending, from_urdf(joint->parent_to_joint_origin_transform));
    if (joint->type == urdf::Joint::FIXED) continue;
    // "line N: <joint name=...>", for messages only (finding the line reads the text).
    auto where = [&] { return element_at(text, r.xml, "joint", joint->name); };
    if (joint->type != urdf::Joint::REVOLUTE && joint->type != urdf::Joint::CONTINUOUS &&
        joint->type != urdf::Joint::PRISMATIC)
      throw UrdfError(where() + " is " + joint_type_name(joint->type) +
                      "; expected revolute, continuous, prismatic or fixed joints between " +
                      "base and tip");
    if (joint->mimic)
      throw UrdfError(where() +
                      " mimics another joint; kincal needs every moving joint as an actuator");
    check_name(text, r.xml, "joint", joint->name,
               "names a measurement column and parameters after each moving joint");
    UrdfArmJoint j;
    j.name = joint->name;
    j.type = joint->type == urdf::Joint::REVOLUTE     ? UrdfJointType::kRevolute
             : joint->type == urdf::Joint::CONTINUOUS ? UrdfJointType::kContinuous
                                                      : UrdfJointType::kPrismatic;
    j.origin = frame_parameters(pending);
    pending = Pose{};
    j.axis = Vector3d(joint->axis.x, joint->axis.y, joint->axis.z);
    if (!(j.axis.norm() > 1e-9)) throw UrdfError(where() + " has a zero axis");
    j.axis.normalize();
    const bool prismatic = j.type == UrdfJointType::kPrismatic;
    const double unit = prismatic ? kMillimetresPerMetre : 1.0;
    if (j.type == UrdfJointType::kContinuous) {
      j.lower = j.upper = NAN;
    } else {
      if (!joint->limits) throw UrdfError(where() + " has no <limit> (required for its type)");
      const double lower = joint->limits->lower, upper = joint->limits->upper;
      const std::string limit =
          "<limit lower=\"" + full(lower) + "\" upper=\"" + full(upper) + "\">";
      if (!(lower <= upper)) throw UrdfError(where() + ": " + limit + ": lower is above upper");
      j.lower = lower * unit;
      j.upper = upper * unit;
      // The model file holds the limits in mm or degrees.
      const double file_unit = prismatic ? 1.0 : kDegreesPerRadian;
      if (!std::isfinite(j.lower * file_unit) || !std::isfinite(j.upper * file_unit))
        throw UrdfError(where() + ": " + limit + " is beyond the largest number of " +
                        (prismatic ? "mm" : "degrees") + " a model file holds");
      if (!(j.lower <= 0 && 0 <= j.upper)) j.home = 0.5 * j.lower + 0.5 * j.upper;
    }
    g.joints.push_back(j);
  }
  if (g.joints.empty())
    throw UrdfError("no moving joint between link '" + message_excerpt(g.base_link) +
                    "' and link '" + message_excerpt(tip_link) + "'");
  g.tip = frame_parameters(pending);
  // Kept for --compliance (off here: a model file writes the masses only when it uses them).
  g.compliance.links = chain_masses(*model, chain);
  if (!g.compliance.links.empty()) g.compliance.masses_source = "URDF inertials";
  return g;
}

// A change to the text: bytes [begin, end) replaced by `text` (an insertion when equal).
struct Edit {
  std::size_t begin, end;
  std::string text;
};

std::string apply_edits(const std::string& text, std::vector<Edit> edits) {
  std::stable_sort(edits.begin(), edits.end(),
                   [](const Edit& a, const Edit& b) { return a.begin < b.begin; });
  std::string out;
  std::size_t at = 0;
  for (const Edit& e : edits) {
    if (e.begin < at) throw std::logic_error("overlapping edits of a URDF");
    out.append(text, at, e.begin - at);
    out += e.text;
    at = e.end;
  }
  out.append(text, at, std::string::npos);
  return out;
}

std::string xyz_text(const Pose& pose) {
  const Vector6d f = frame_parameters(pose);
  return full(f[0] / kMillimetresPerMetre) + " " + full(f[1] / kMillimetresPerMetre) + " " +
         full(f[2] / kMillimetresPerMetre);
}

std::string rpy_text(const Pose& pose) {
  const Vector6d f = frame_parameters(pose);
  return full(f[3]) + " " + full(f[4]) + " " + full(f[5]);
}

// The edits that make joint element `joint`'s origin `pose`: the values of its <origin>'s
// xyz and rpy (the attributes added when missing), or an <origin> added as its first child.
void set_origin(const std::string& text, const XmlText& xml, int joint, const Pose& pose,
                std::vector<Edit>& edits) {
  const std::string xyz = xyz_text(pose), rpy = rpy_text(pose);
  const int o = xml.child(joint, "origin");
  if (o >= 0) {
    const XmlElement& origin = xml.elements[static_cast<std::size_t>(o)];
    std::string missing;
    for (const auto& [key, value] : {std::pair{"xyz", xyz}, std::pair{"rpy", rpy}}) {
      if (const XmlAttribute* a = origin.attribute(key))
        edits.push_back({a->value_begin, a->value_end, a->quote ? value : '"' + value + '"'});
      else
        missing += std::string(" ") + key + "=\"" + value + "\"";
    }
    const std::size_t close = origin.empty ? origin.close_begin : origin.tag_end - 1;
    if (!missing.empty()) edits.push_back({close, close, missing});
    return;
  }
  const XmlElement& j = xml.elements[static_cast<std::size_t>(joint)];
  const std::string element = "<origin xyz=\"" + xyz + "\" rpy=\"" + rpy + "\"/>";
  if (j.empty) {
    edits.push_back({j.close_begin, j.end, ">" + element + "</" + j.name + ">"});
    return;
  }
  // Before its first child, with the white space that separates its children.
  std::size_t k = j.tag_end;
  while (k < j.close_begin &&
         (text[k] == ' ' || text[k] == '\t' || text[k] == '\r' || text[k] == '\n'))
    ++k;
  edits.push_back({j.tag_end, j.tag_end, text.substr(j.tag_end, k - j.tag_end) + element});
}

bool same_pose(const Pose& a, const Pose& b) {
  return (a.translation - b.translation).norm() <= 1e-9 * (1 + a.translation.norm()) &&
         (a.rotation - b.rotation).norm() <= 1e-9;
}

}  // namespace

UrdfArmGeometry import_urdf(const std::string& text, const std::string& file,
                            const std::string& base_link, const std::string& tip_link) {
  return import_read(read_urdf(text), text, file, base_link, tip_link);
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
  ReadUrdf read;
  UrdfArmGeometry text_geometry;
  try {
    read = read_urdf(g.urdf_text);
    text_geometry = import_read(read, g.urdf_text, "", g.base_link, g.tip_link);
  } catch (const UrdfError& e) {
    throw UrdfError(std::string("the model's URDF text (mechanism.urdf.text), ") + e.what());
  }
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

  const urdf::ModelInterfaceSharedPtr& urdf_model = read.model;
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

  // The edits: the origins' values, the added links and joints before </robot>, the header
  // first. Every other byte of the user's text stays as it is.
  const std::string& text = g.urdf_text;
  const XmlText& xml = read.xml;
  const XmlElement& robot = xml.elements[static_cast<std::size_t>(xml.root)];
  if (robot.name != "robot" || robot.empty)
    throw UrdfError("the URDF's root element is not <robot> with links and joints");
  std::vector<Edit> edits;
  // The origins to write, by joint name: the chain's corrected (a joint without correction
  // keeps its text), and with a root `world`, every joint from it moved by where the root is
  // in the measurement frame.
  std::map<std::string, Pose> origins;
  for (const UrdfArmJoint& joint : g.joints) {
    if (joint.origin_error.isZero(0) && joint.offset == 0) continue;
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
    const int element = xml.child(xml.root, "joint", "name", name);
    if (element < 0)
      throw UrdfError("joint '" + message_excerpt(name) + "' not found in the URDF text");
    set_origin(text, xml, element, pose, edits);
  }
  auto unique_joint_name = [&](std::string name) {
    while (urdf_model->getJoint(name)) name += "_";
    return name;
  };
  auto comment = [](const std::string& what) { return "<!--" + xml_comment_text(what) + "-->"; };
  auto fixed_joint = [](const std::string& name, const std::string& parent,
                        const std::string& child, const Pose& pose) {
    return "  <joint name=\"" + xml_attribute_text(name) + "\" type=\"fixed\">\n" +
           "    <parent link=\"" + xml_attribute_text(parent) + "\"/>\n" + "    <child link=\"" +
           xml_attribute_text(child) + "\"/>\n" + "    <origin xyz=\"" + xyz_text(pose) +
           "\" rpy=\"" + rpy_text(pose) + "\"/>\n  </joint>\n";
  };
  const std::string world_joint = unique_joint_name("world_to_" + root);
  const std::string tcp_joint = unique_joint_name(g.tip_link + "_to_tcp");
  std::string added = text[robot.close_begin - 1] == '\n' ? "" : "\n";
  if (root_is_world) {
    added += "  " +
             comment(" kincal: the root link world is the measurement frame (" + frames.sensor +
                     "): the joints from it carry the calibrated base ") +
             "\n";
  } else {
    added +=
        "  " +
        comment(" kincal: the measurement frame (" + frames.sensor + ") and the calibrated base ") +
        "\n  <link name=\"world\"/>\n" + fixed_joint(world_joint, "world", root, world_from_root);
  }
  added += "  " +
           comment(" kincal: the measured point or frame (tool frame, and a tracker's target) ") +
           "\n  <link name=\"tcp\"/>\n" + fixed_joint(tcp_joint, g.tip_link, "tcp", tcp);
  edits.push_back({robot.close_begin, robot.close_begin, added});
  // The header goes first in the document, after the XML declaration.
  const std::size_t first = xml.prolog_end;
  const bool after_declaration = first > 0 && text[first - 1] == '>';
  edits.push_back(
      {first, first, after_declaration ? "\n" + comment(header) : comment(header) + "\n"});
  const std::string out = apply_edits(text, std::move(edits));

  // What urdfdom reads from the result must be the user's robot with those origins, and the
  // two links and joints added: a check of the edits against TinyXML's reading.
  std::string wrong;
  try {
    const ReadUrdf back = read_urdf(out);
    auto check_joint = [&](const std::string& name, const std::string& parent,
                           const std::string& child, const Pose& pose) {
      const urdf::JointConstSharedPtr j = back.model->getJoint(name);
      if (!j || j->parent_link_name != parent || j->child_link_name != child ||
          !same_pose(from_urdf(j->parent_to_joint_origin_transform), pose))
        wrong = "joint '" + name + "'";
    };
    for (const auto& [name, joint] : urdf_model->joints_) {
      const auto it = origins.find(name);
      check_joint(
          name, joint->parent_link_name, joint->child_link_name,
          it != origins.end() ? it->second : from_urdf(joint->parent_to_joint_origin_transform));
      const urdf::JointConstSharedPtr j = back.model->getJoint(name);
      if (j && j->type != joint->type) wrong = "joint '" + name + "'";
    }
    if (!root_is_world) check_joint(world_joint, "world", root, world_from_root);
    check_joint(tcp_joint, g.tip_link, "tcp", tcp);
    if (back.model->links_.size() != urdf_model->links_.size() + (root_is_world ? 1 : 2) ||
        back.model->joints_.size() != urdf_model->joints_.size() + (root_is_world ? 1 : 2))
      wrong = "the number of links or joints";
  } catch (const UrdfError& e) {
    wrong = e.what();
  }
  if (!wrong.empty())
    throw UrdfError("the corrected URDF does not read back as written (" + wrong +
                    "); this is a fault in kincal: please report it with the model file");
  return out;
}

std::shared_ptr<MeasurementModel> model_from_urdf(const std::string& text, const std::string& file,
                                                  const UrdfModelOptions& options) {
  if (options.sensor != "point-tracker" && options.sensor != "pose-tracker")
    throw std::invalid_argument("sensor '" + options.sensor +
                                "': expected point-tracker or pose-tracker");
  if (options.sensor != "point-tracker" && !options.point.isZero())
    throw std::invalid_argument(
        "a point is the target of a point tracker; a pose tracker's marker is its target "
        "(x, y, z and three angles)");
  if (options.sensor == "point-tracker" && !options.target.isZero())
    throw std::invalid_argument(
        "a target frame is a pose tracker's marker; a point tracker's target is its point");
  if (!options.frame.allFinite() || !options.target.allFinite() || !options.point.allFinite())
    throw std::invalid_argument("the tracker's frame, target or point is not finite");
  UrdfArmGeometry geometry = import_urdf(text, file, options.base_link, options.tip_link);
  if (options.compliance != UrdfCompliance::kNone) {
    ComplianceSpec& c = geometry.compliance;
    c.enabled = true;
    if (options.compliance == UrdfCompliance::kInertials && c.links.empty())
      throw std::invalid_argument(
          "the URDF has no <inertial> masses on the chain: use fitted masses (--compliance "
          "fitted)");
    const bool fitted = options.compliance == UrdfCompliance::kFitted ||
                        (options.compliance == UrdfCompliance::kAuto && c.links.empty());
    if (fitted) {
      c.masses = GravityMasses::kFitted;
      c.links.clear();
      c.masses_source.clear();
    }
    c.payload_column = options.payload_column;
    c.payload.centre = options.payload_centre;
  } else {
    geometry.compliance = ComplianceSpec{};
  }
  std::shared_ptr<const Mechanism> arm = std::make_shared<UrdfArm>(std::move(geometry));
  std::shared_ptr<const Sensor> tracker;
  if (options.sensor == "point-tracker")
    tracker = std::make_shared<PointTracker>("tracker", options.frame, options.point);
  else
    tracker = std::make_shared<PoseTracker>("tracker", options.frame, options.target);
  auto model =
      std::make_shared<MeasurementModel>(arm, std::vector<std::shared_ptr<const Sensor>>{tracker});
  model->parameters().set_free("*", true);
  // Gravity's tilt acts only through the compliances (zero at the start): it is freed by hand.
  if (options.compliance != UrdfCompliance::kNone) model->parameters().set_free("gravity.*", false);
  // The model file written from a URDF is one kincal reads: within a model file's size (the
  // URDF's text grows when escaped as JSON) and accepted by the model reader. import_urdf
  // refuses what it knows the reader would; this catches the rest before anything is written.
  const std::string model_text =
      model_to_json(*model, model->parameters().nominal_values()).dump(2) + "\n";
  const JsonLimits limits;
  if (model_text.size() > limits.max_bytes)
    throw std::invalid_argument("the model file would be " + std::to_string(model_text.size()) +
                                " bytes (the URDF's text, escaped as JSON, and the model), more "
                                "than the " +
                                std::to_string(limits.max_bytes >> 20) +
                                " MiB a model file may have");
  try {
    model_from_json(parse_json_text(model_text, "the model file"), "the model file");
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("the model imported from it would not read back: ") +
                                e.what());
  }
  return model;
}

}  // namespace kincal
