#include "kincal/models/export_formats.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/framework/kinematics/names.hpp"
#include "kincal/framework/kinematics/pose.hpp"
#include "kincal/framework/kinematics/units.hpp"
#include "kincal/models/model_io.hpp"
#include "kincal/models/serial_arm.hpp"
#include "kincal/models/urdf_arm.hpp"
#include "kincal/models/urdf_io.hpp"

namespace kincal {

namespace {

using Json = nlohmann::ordered_json;

std::string full(double v) {
  if (v == 0) v = 0;  // no "-0" in a table a person reads
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// Metres per unit of a length: URDF is in metres, kincal's lengths carry their unit.
double metres_per(const std::string& unit) {
  if (unit == kMillimetre) return 1e-3;
  throw ExportError("length unit '" + unit + "' has no conversion to metres");
}

VectorXd mechanism_values(const MeasurementModel& model) {
  return model.parameters().nominal_values().head(
      static_cast<int>(model.mechanism().parameters().size()));
}

const SerialArm* as_serial_arm(const MeasurementModel& model) {
  return dynamic_cast<const SerialArm*>(&model.mechanism());
}

// The constant part of link i (everything but the joint's own motion Rz(q) or Tz(q), which
// comes first in A_i): Rz(theta) Tz(d) Tx(a) Rx(alpha) or Rz(theta) Tx(a) Rx(alpha) Ry(beta).
Pose link_constant(const SerialJoint& j) {
  const Matrix3d Rz = Eigen::AngleAxisd(j.theta, Vector3d::UnitZ()).toRotationMatrix();
  const Matrix3d Rx = Eigen::AngleAxisd(j.alpha, Vector3d::UnitX()).toRotationMatrix();
  Pose p;
  if (j.convention == LinkConvention::kDh) {
    p.translation = Vector3d(0, 0, j.d) + Rz * Vector3d(j.a, 0, 0);
    p.rotation = Rz * Rx;
  } else {
    const Matrix3d Ry = Eigen::AngleAxisd(j.beta, Vector3d::UnitY()).toRotationMatrix();
    p.translation = Rz * Vector3d(j.a, 0, 0);
    p.rotation = Rz * Rx * Ry;
  }
  return p;
}

std::string origin(const Pose& p, double metres) {
  const Vector6d f = frame_parameters(p);
  return "<origin xyz=\"" + full(f[0] * metres) + " " + full(f[1] * metres) + " " +
         full(f[2] * metres) + "\" rpy=\"" + full(f[3]) + " " + full(f[4]) + " " + full(f[5]) +
         "\"/>";
}

Json pose_json(const Pose& p) {
  const Vector6d f = frame_parameters(p);
  return {{"position", {f[0], f[1], f[2]}}, {"rotation_zyx_rad", {f[3], f[4], f[5]}}};
}

// A parallel mechanism's legs by the naming convention <actuator>.base.{x,y[,z]},
// <actuator>.platform.{x,y[,z]}, <actuator>.offset.
struct Leg {
  std::string name;
  Vector3d base = Vector3d::Zero(), platform = Vector3d::Zero();
  double offset = 0, home_actuator = NAN;
};

std::vector<Leg> parallel_legs(const MeasurementModel& model) {
  const Mechanism& m = model.mechanism();
  const VectorXd values = mechanism_values(model);
  auto value_of = [&](const std::string& name, double fallback, bool required) {
    for (std::size_t i = 0; i < m.parameters().size(); ++i)
      if (m.parameters()[i].name == name) return values[static_cast<int>(i)];
    if (required)
      throw ExportError("mechanism '" + m.type() + "' has no parameter " + name +
                        "; the joint-coordinate table is for parallel mechanisms whose legs "
                        "have base and platform joints (hexapod-6ups, planar-3rpr)");
    return fallback;
  };
  VectorXd home(static_cast<int>(m.actuators().size()));
  const bool home_ok = m.home_actuators(values, home).ok();
  std::vector<Leg> legs;
  for (std::size_t a = 0; a < m.actuators().size(); ++a) {
    Leg leg;
    leg.name = m.actuators()[a].name;
    for (int k = 0; k < 3; ++k) {
      const std::string axis(1, static_cast<char>('x' + k));
      leg.base[k] = value_of(leg.name + ".base." + axis, 0.0, k < 2);
      leg.platform[k] = value_of(leg.name + ".platform." + axis, 0.0, k < 2);
    }
    leg.offset = value_of(leg.name + ".offset", 0.0, true);
    if (home_ok) leg.home_actuator = home[static_cast<int>(a)];
    legs.push_back(leg);
  }
  return legs;
}

const char* kLegConvention =
    "leg length = actuator value + offset = |t + R p - b| (b: base joint in the base frame, p: "
    "platform joint in the platform frame, pose (R, t) of the platform frame in the base "
    "frame). A controller that computes the length L of a leg from the pose commands the "
    "actuator value L - offset; an encoder that reads 0 at a reference mark has as offset the "
    "leg length at that mark";

// The measurement frame and the measured point, from the model's one tracker or its sockets;
// none when it has neither (nothing the export could drop moves a tcp then).
bool tracker_frames(const MeasurementModel& model, MeasuredFrames& frames) {
  int measuring = 0;
  for (const auto& sensor : model.sensors())
    measuring += sensor->type() == "point-tracker" || sensor->type() == "pose-tracker" ||
                 sensor->type() == "socket";
  if (measuring == 0) return false;
  try {
    frames = measured_frames(model, model.parameters().nominal_values());
  } catch (const UrdfError& e) {
    throw ExportError(std::string("--format urdf: ") + e.what());
  }
  return true;
}

}  // namespace

std::string export_urdf(const MeasurementModel& model, const ExportSource& source) {
  if (const auto* urdf_arm = dynamic_cast<const UrdfArm*>(&model.mechanism())) {
    std::string header =
        " kincal export: calibrated from " + source.model_file + " (sha256 " + source.sha256 +
        "). The robot's own URDF with the calibrated joint origins (origin * origin error * "
        "offset) and two fixed joints added: from the root link `world` (the frame the "
        "measurements were taken in) to the robot, and from the tip link to `tcp` (the "
        "measured point or frame). ";
    if (urdf_arm->has_compliance())
      header +=
          "It holds the geometry only: the joints' compliance under gravity stays in the model "
          "file, and loading this URDF alone leaves the deflection uncorrected (the calibration "
          "report says by how much at the measured configurations); kincal compensate writes "
          "joint commands that include it. ";
    try {
      return export_urdf_arm(model, model.parameters().nominal_values(), header);
    } catch (const UrdfError& e) {
      throw ExportError(std::string("--format urdf: ") + e.what());
    }
  }
  const SerialArm* arm = as_serial_arm(model);
  if (!arm)
    throw ExportError("--format urdf: mechanism '" + model.mechanism().type() +
                      "' is not a serial arm (URDF describes serial chains); use --format csv "
                      "or json for a parallel mechanism");
  const SerialArmGeometry g = arm->geometry_from(mechanism_values(model));
  MeasuredFrames frames;
  const bool with_tracker = tracker_frames(model, frames);
  const double m = metres_per(kMillimetre);
  std::string out = "<?xml version=\"1.0\"?>\n<!-- kincal export: calibrated serial arm from " +
                    xml_comment_text(source.model_file) + " (sha256 " + source.sha256 +
                    ").\n     Lengths in metres, angles in radians. Joint i's origin is the "
                    "calibrated constant part of link i-1\n     (DH: Rz(theta) Tz(d) Tx(a) "
                    "Rx(alpha); Hayati: Rz(theta) Tx(a) Rx(alpha) Ry(beta)), the base frame "
                    "for joint 1;\n     every joint moves about (or along) its own z axis, "
                    "q = 0 is kincal's q = 0. Limits are home +- the\n     actuator's "
                    "calibration range, not the machine's hard limits; effort and velocity are "
                    "not known to kincal (0).";
  out += with_tracker ? "\n     world: the frame the measurements were taken in (" +
                            xml_comment_text(frames.sensor) +
                            "); tcp: the\n     measured point or frame (tool frame, and a "
                            "tracker's target or marker). -->\n"
                      : "\n     The model has no tracker or socket: no world or tcp link. -->\n";
  out += "<robot name=\"kincal_calibrated\">\n";
  if (with_tracker)
    out +=
        "  <link name=\"world\"/>\n  <joint name=\"world_to_base_link\" type=\"fixed\">\n"
        "    <parent link=\"world\"/>\n    <child link=\"base_link\"/>\n    " +
        origin(frames.world_from_mechanism, m) + "\n  </joint>\n";
  out += "  <link name=\"base_link\"/>\n";
  Pose previous = frame_from_parameters(g.base);
  std::string parent = "base_link";
  for (std::size_t i = 0; i < g.joints.size(); ++i) {
    const SerialJoint& j = g.joints[i];
    const bool revolute = j.type == JointType::kRevolute;
    const double range = model.actuator_ranges()[static_cast<int>(i)];
    const double scale = revolute ? 1.0 : m;
    const std::string child = j.name + "_link";
    out += "  <link name=\"" + xml_attribute_text(child) + "\"/>\n";
    out += "  <joint name=\"" + xml_attribute_text(j.name) + "\" type=\"" +
           (revolute ? "revolute" : "prismatic") + "\">\n    <parent link=\"" +
           xml_attribute_text(parent) + "\"/>\n    <child link=\"" + xml_attribute_text(child) +
           "\"/>\n    " + origin(previous, m) + "\n    <axis xyz=\"0 0 1\"/>\n    <limit lower=\"" +
           full((j.home - range) * scale) + "\" upper=\"" + full((j.home + range) * scale) +
           "\" effort=\"0\" velocity=\"0\"/>\n  </joint>\n";
    previous = link_constant(j);
    parent = child;
  }
  out += "  <link name=\"tool0\"/>\n  <joint name=\"tool\" type=\"fixed\">\n    <parent link=\"" +
         xml_attribute_text(parent) + "\"/>\n    <child link=\"tool0\"/>\n    " +
         origin(compose(previous, frame_from_parameters(g.tool)), m) + "\n  </joint>\n";
  if (with_tracker)
    out +=
        "  <link name=\"tcp\"/>\n  <joint name=\"tool0_to_tcp\" type=\"fixed\">\n"
        "    <parent link=\"tool0\"/>\n    <child link=\"tcp\"/>\n    " +
        origin(frames.tcp_in_tool, m) + "\n  </joint>\n";
  out += "</robot>\n";
  return out;
}

std::string export_csv(const MeasurementModel& model, const ExportSource& source) {
  // One comment line, whatever the name holds: control characters and bytes that are not
  // UTF-8 as \xNN (docs/reliability.md, "Names").
  const std::string file = printable(source.model_file);
  std::string out = "# kincal export: calibrated " + model.mechanism().type() + " from " + file +
                    " (sha256 " + source.sha256 + ")\n";
  if (dynamic_cast<const UrdfArm*>(&model.mechanism()))
    throw ExportError(
        "--format csv: an arm imported from a URDF has no DH table; use --format "
        "urdf (its own URDF, corrected) or json (origins, errors and offsets)");
  if (const SerialArm* arm = as_serial_arm(model)) {
    const SerialArmGeometry g = arm->geometry_from(mechanism_values(model));
    out +=
        "# one row per joint, base to tool; link i = Rz(theta + q) Tz(d) Tx(a) Rx(alpha) "
        "(dh) or Rz(theta + q) Tx(a) Rx(alpha) Ry(beta) (hayati); a prismatic joint adds q "
        "to d\n# lengths mm, angles deg; home and range in the joint's unit (deg or mm)\n";
    const Vector6d b = g.base, t = g.tool;
    out += "# base frame: x,y,z mm " + full(b[0]) + "," + full(b[1]) + "," + full(b[2]) +
           "; rotation_zyx_deg " + full(b[3] * kDegreesPerRadian) + "," +
           full(b[4] * kDegreesPerRadian) + "," + full(b[5] * kDegreesPerRadian) + "\n";
    out += "# tool frame: x,y,z mm " + full(t[0]) + "," + full(t[1]) + "," + full(t[2]) +
           "; rotation_zyx_deg " + full(t[3] * kDegreesPerRadian) + "," +
           full(t[4] * kDegreesPerRadian) + "," + full(t[5] * kDegreesPerRadian) + "\n";
    out += "joint,type,convention,a_mm,alpha_deg,d_mm,beta_deg,theta_deg,home,range\n";
    for (std::size_t i = 0; i < g.joints.size(); ++i) {
      const SerialJoint& j = g.joints[i];
      const bool revolute = j.type == JointType::kRevolute;
      const bool dh = j.convention == LinkConvention::kDh;
      const double unit = revolute ? kDegreesPerRadian : 1.0;
      out += j.name + "," + to_string(j.type) + "," + to_string(j.convention) + "," + full(j.a) +
             "," + full(j.alpha * kDegreesPerRadian) + "," + (dh ? full(j.d) : "") + "," +
             (dh ? "" : full(j.beta * kDegreesPerRadian)) + "," +
             full(j.theta * kDegreesPerRadian) + "," + full(j.home * unit) + "," +
             full(model.actuator_ranges()[static_cast<int>(i)] * unit) + "\n";
    }
    return out;
  }
  const std::vector<Leg> legs = parallel_legs(model);
  const Vector6d home = frame_parameters(model.mechanism().home_pose());
  out += "# " + std::string(kLegConvention) + ".\n";
  out +=
      "# lengths mm; home_actuator is the actuator value at home_pose, home_length = "
      "home_actuator + offset\n";
  out += "# home_pose: position_mm " + full(home[0]) + "," + full(home[1]) + "," + full(home[2]) +
         "; rotation_zyx_deg " + full(home[3] * kDegreesPerRadian) + "," +
         full(home[4] * kDegreesPerRadian) + "," + full(home[5] * kDegreesPerRadian) +
         " (R = Rz(rz) Ry(ry) Rx(rx))\n";
  out +=
      "leg,base_x,base_y,base_z,platform_x,platform_y,platform_z,offset,home_actuator,"
      "home_length\n";
  for (const Leg& l : legs)
    out += l.name + "," + full(l.base.x()) + "," + full(l.base.y()) + "," + full(l.base.z()) + "," +
           full(l.platform.x()) + "," + full(l.platform.y()) + "," + full(l.platform.z()) + "," +
           full(l.offset) + "," + full(l.home_actuator) + "," + full(l.home_actuator + l.offset) +
           "\n";
  return out;
}

std::string export_json(const MeasurementModel& model, const ExportSource& source) {
  Json out;
  out["format"] = "kincal-export";
  out["version"] = 1;
  // JSON holds UTF-8 only: a file name that is not is written as printable() shows it.
  out["source"] = {{"model", is_valid_utf8(source.model_file) ? source.model_file
                                                              : printable(source.model_file)},
                   {"sha256", source.sha256}};
  out["mechanism"] = model.mechanism().type();
  out["units"] = {{"length", "mm"}, {"angle", "rad"}};
  if (const auto* urdf_arm = dynamic_cast<const UrdfArm*>(&model.mechanism())) {
    const UrdfArmGeometry g = urdf_arm->geometry_from(mechanism_values(model));
    out["convention"] =
        "T(q) = base * prod_i [origin_i * origin_error_i * motion_i(q_i + offset_i)] * tip * "
        "tool; motion: rotation about axis (revolute, continuous) or translation along it "
        "(prismatic); frames: R = Rz(rz) Ry(ry) Rx(rx); world = the tracker's frame, tcp = "
        "tool * target or marker";
    out["urdf_file"] = g.urdf_file;
    out["base_link"] = g.base_link;
    out["tip_link"] = g.tip_link;
    out["base"] = pose_json(frame_from_parameters(g.base));
    out["joints"] = Json::array();
    for (const UrdfArmJoint& j : g.joints) {
      Json joint = {{"name", j.name},
                    {"type", to_string(j.type)},
                    {"origin", pose_json(frame_from_parameters(j.origin))},
                    {"axis", {j.axis.x(), j.axis.y(), j.axis.z()}},
                    {"origin_error", pose_json(frame_from_parameters(j.origin_error))},
                    {"offset", j.offset}};
      if (j.type != UrdfJointType::kContinuous) {
        joint["lower"] = j.lower;
        joint["upper"] = j.upper;
      }
      out["joints"].push_back(joint);
    }
    out["tip"] = pose_json(frame_from_parameters(g.tip));
    out["tool"] = pose_json(frame_from_parameters(g.tool));
    if (urdf_arm->has_compliance()) {
      // delta_i = c_i tau_i(q) (or the fitted moments) added to q_i: docs/theory.md.
      Json values = Json::object();
      const VectorXd v = mechanism_values(model);
      for (int k : urdf_arm->non_geometric_parameters()) {
        const Parameter& p = model.parameters()[k];
        values[p.name] = {{"value", v[k]}, {"unit", p.unit}};
      }
      out["compliance"] = {
          {"masses", to_string(g.compliance.masses)},
          {"gravity_in_base_link",
           {g.compliance.gravity.x(), g.compliance.gravity.y(), g.compliance.gravity.z()}},
          {"parameters", values}};
    }
    MeasuredFrames frames;
    if (tracker_frames(model, frames)) {
      out["world_from_base_frame"] = pose_json(frames.world_from_mechanism);
      out["tcp_in_tool"] = pose_json(frames.tcp_in_tool);
    }
    return out.dump(2) + "\n";
  }
  if (const SerialArm* arm = as_serial_arm(model)) {
    const SerialArmGeometry g = arm->geometry_from(mechanism_values(model));
    out["convention"] =
        "T(q) = base * A_1(q_1) ... A_N(q_N) * tool; dh: A_i = Rz(theta + q) Tz(d) Tx(a) "
        "Rx(alpha), hayati: A_i = Rz(theta + q) Tx(a) Rx(alpha) Ry(beta); a prismatic joint "
        "adds q to d; frames: R = Rz(rz) Ry(ry) Rx(rx)";
    out["base"] = pose_json(frame_from_parameters(g.base));
    out["joints"] = Json::array();
    for (std::size_t i = 0; i < g.joints.size(); ++i) {
      const SerialJoint& j = g.joints[i];
      const double range = model.actuator_ranges()[static_cast<int>(i)];
      Json joint = {{"name", j.name},
                    {"type", to_string(j.type)},
                    {"convention", to_string(j.convention)},
                    {"a", j.a},
                    {"alpha", j.alpha}};
      if (j.convention == LinkConvention::kDh)
        joint["d"] = j.d;
      else
        joint["beta"] = j.beta;
      joint["theta"] = j.theta;
      joint["home"] = j.home;
      joint["lower"] = j.home - range;
      joint["upper"] = j.home + range;
      out["joints"].push_back(joint);
    }
    out["tool"] = pose_json(frame_from_parameters(g.tool));
    return out.dump(2) + "\n";
  }
  std::vector<Leg> legs;
  try {
    legs = parallel_legs(model);
  } catch (const ExportError&) {
    // Any other mechanism (a plug-in's): its own model-file description with the calibrated
    // values, which its type's reader defines, and the parameters by name.
    const VectorXd values = model.parameters().nominal_values();
    const Mechanism& m = model.mechanism();
    out["convention"] =
        "description: the mechanism as in a kincal model file (the fields its type defines), "
        "with the calibrated values; parameters: the same values by name with their units; "
        "actuators: their values at the home pose";
    Json description = model_to_json(model, values)["mechanism"];
    out["description"] = description;
    out["home_pose"] = pose_json(m.home_pose());
    out["parameters"] = Json::array();
    for (std::size_t i = 0; i < m.parameters().size(); ++i)
      out["parameters"].push_back({{"name", m.parameters()[i].name},
                                   {"value", values[static_cast<int>(i)]},
                                   {"unit", m.parameters()[i].unit}});
    VectorXd home(m.num_actuators());
    const bool home_ok = m.home_actuators(values.head(m.num_parameters()), home).ok();
    out["actuators"] = Json::array();
    for (int a = 0; a < m.num_actuators(); ++a)
      out["actuators"].push_back({{"name", m.actuators()[static_cast<std::size_t>(a)].name},
                                  {"unit", m.actuators()[static_cast<std::size_t>(a)].unit},
                                  {"home", home_ok ? Json(home[a]) : Json()}});
    return out.dump(2) + "\n";
  }
  out["convention"] = kLegConvention;
  out["home_pose"] = pose_json(model.mechanism().home_pose());
  out["legs"] = Json::array();
  for (const Leg& l : legs)
    out["legs"].push_back({{"name", l.name},
                           {"base", {l.base.x(), l.base.y(), l.base.z()}},
                           {"platform", {l.platform.x(), l.platform.y(), l.platform.z()}},
                           {"offset", l.offset},
                           {"home_actuator", l.home_actuator},
                           {"home_length", l.home_actuator + l.offset}});
  return out.dump(2) + "\n";
}

std::string export_model(const MeasurementModel& model, const std::string& format,
                         const ExportSource& source) {
  // Formats beyond kincal's own are registered per mechanism type (a plug-in's).
  const ModelRegistry& registry = ModelRegistry::global();
  const std::string& type = model.mechanism().type();
  if (const ExportFormat* registered = registry.export_format(type, format))
    return registered->write(model, {source.model_file, source.sha256});
  if (format == "urdf") return export_urdf(model, source);
  if (format == "csv") return export_csv(model, source);
  if (format == "json") return export_json(model, source);
  if (format == "camera-info") return export_camera_info(model, source);
  std::string known = "urdf, csv, json, camera-info";
  for (const auto& f : registry.export_formats())
    if (f.mechanism_type == type) known += ", " + f.format;
  throw std::invalid_argument("format '" + format + "': expected " + known + " for mechanism '" +
                              type + "'");
}

}  // namespace kincal
