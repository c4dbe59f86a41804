#include "kincal/models/urdf_arm.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <set>
#include <stdexcept>

#include "kincal/framework/analysis/identifiability.hpp"
#include "kincal/models/compliant_chain.hpp"

namespace kincal {

using serial_chain::add_frame_parameters;

const char* to_string(UrdfJointType type) {
  switch (type) {
    case UrdfJointType::kRevolute:
      return "revolute";
    case UrdfJointType::kContinuous:
      return "continuous";
    case UrdfJointType::kPrismatic:
      return "prismatic";
  }
  return "revolute";
}

namespace {

bool finite(const Pose& p) { return p.rotation.allFinite() && p.translation.allFinite(); }

bool is_revolute(UrdfJointType type) { return type != UrdfJointType::kPrismatic; }

}  // namespace

Pose urdf_joint_motion(const UrdfArmJoint& joint, double value) {
  Pose m;
  if (is_revolute(joint.type))
    m.rotation = Eigen::AngleAxisd(value, joint.axis).toRotationMatrix();
  else
    m.translation = value * joint.axis;
  return m;
}

UrdfArm::UrdfArm(UrdfArmGeometry geometry) : geometry_(std::move(geometry)) {
  auto& joints = geometry_.joints;
  if (joints.empty())
    throw std::invalid_argument("a URDF arm needs at least one moving joint between base and tip");
  std::set<std::string> names;
  add_frame_parameters(parameters_, "base", geometry_.base);
  for (std::size_t i = 0; i < joints.size(); ++i) {
    UrdfArmJoint& j = joints[i];
    const std::string where = "URDF arm joint " + std::to_string(i + 1) + " ('" + j.name + "')";
    if (j.name.empty() || j.name == "base" || j.name == "tool" || !names.insert(j.name).second)
      throw std::invalid_argument(where + ": expected a unique name other than 'base' and 'tool'");
    if (!j.origin.allFinite() || !j.axis.allFinite() || !j.origin_error.allFinite() ||
        !std::isfinite(j.offset) || !std::isfinite(j.home))
      throw std::invalid_argument(where + ": non-finite value");
    const double norm = j.axis.norm();
    if (!(norm > 1e-9)) throw std::invalid_argument(where + ": the joint axis is zero");
    j.axis /= norm;
    const bool revolute = is_revolute(j.type);
    if (!(j.range > 0) || !std::isfinite(j.range))
      j.range = revolute ? kDefaultRevoluteRange : kDefaultPrismaticRange;
    add_frame_parameters(parameters_, j.name + ".origin", j.origin_error);
    parameters_.push_back({j.name + ".offset", j.offset, revolute ? "rad" : "mm", false});
    actuators_.push_back({j.name, revolute ? "rad" : "mm", j.range});
    // NaN: a continuous joint; equal limits (a joint built in code without any): none.
    if (std::isfinite(j.lower) && std::isfinite(j.upper) && j.lower < j.upper) {
      actuators_.back().lower = j.lower;
      actuators_.back().upper = j.upper;
    }
    origins_.push_back(frame_from_parameters(j.origin));
  }
  tip_ = frame_from_parameters(geometry_.tip);
  add_frame_parameters(parameters_, "tool", geometry_.tool);
  if (!geometry_.base.allFinite() || !geometry_.tool.allFinite() || !geometry_.tip.allFinite())
    throw std::invalid_argument("URDF arm: non-finite base, tip or tool frame");
  if (geometry_.compliance.enabled) {
    std::vector<std::string> joint_names;
    std::vector<bool> revolute;
    for (const UrdfArmJoint& j : joints) {
      joint_names.push_back(j.name);
      revolute.push_back(is_revolute(j.type));
    }
    compliance_ = JointCompliance(geometry_.compliance, joint_names, revolute);
    // Gravity's chain: the URDF's origins and axes, no error, no offset, the base at identity.
    gravity_params_ = VectorXd::Zero(static_cast<Eigen::Index>(parameters_.size()));
    VectorXd home = VectorXd::Zero(num_joints());
    for (int i = 0; i < num_joints(); ++i) home[i] = joints[static_cast<std::size_t>(i)].home;
    GravityChain at_home;
    gravity_chain(home, at_home);
    compliance_.scale_tolerances(at_home);
    geometry_.compliance = compliance_.spec();  // the gravity direction made unit
    compliance_.add_to(parameters_, actuators_, names, "URDF arm");
  }

  home_q_.resize(num_actuators());
  for (int i = 0; i < num_joints(); ++i) home_q_[i] = joints[i].home;
  if (has_payload_actuator()) home_q_[num_joints()] = 0.5 * geometry_.compliance.payload_max;
  const ForwardKinematicsResult home =
      forward_kinematics(urdf_arm_parameters(geometry_), home_q_, Pose{});
  if (!home.ok()) throw std::invalid_argument("URDF arm: home pose " + home.describe());
  home_pose_ = home.pose;
}

VectorXd urdf_arm_parameters(const UrdfArmGeometry& geometry) {
  const int n = static_cast<int>(geometry.joints.size());
  VectorXd p(UrdfArm::kFrameParameters * 2 + UrdfArm::kJointParameters * n);
  p.head<6>() = geometry.base;
  for (int i = 0; i < n; ++i) {
    p.segment<6>(UrdfArm::joint_index(i)) = geometry.joints[i].origin_error;
    p[UrdfArm::joint_index(i) + UrdfArm::kOffset] = geometry.joints[i].offset;
  }
  p.tail<6>() = geometry.tool;
  if (!geometry.compliance.enabled) return p;
  std::vector<std::string> names;
  std::vector<bool> revolute;
  for (const UrdfArmJoint& j : geometry.joints) {
    names.push_back(j.name);
    revolute.push_back(is_revolute(j.type));
  }
  return JointCompliance(geometry.compliance, names, revolute).appended_to(p);
}

UrdfArmGeometry UrdfArm::geometry_from(const ParamsRef& params) const {
  UrdfArmGeometry g = geometry_;
  g.base = params.segment<6>(base_index());
  for (int i = 0; i < num_joints(); ++i) {
    g.joints[i].origin_error = params.segment<6>(joint_index(i));
    g.joints[i].offset = params[joint_index(i) + kOffset];
  }
  g.tool = params.segment<6>(tool_index());
  if (has_compliance())
    g.compliance =
        compliance_.spec_with(params.segment(compliance_index(), compliance_.num_parameters()));
  return g;
}

InverseKinematicsResult UrdfArm::home_actuators(const ParamsRef&, Eigen::Ref<VectorXd> q) const {
  q = home_q_;
  return {};
}

// Link i for serial_chain::walk: C_i E_i M_i(q_i + o_i). The origin error E_i is a frame
// block after C_i; the offset o_i turns about (or slides along) the joint's axis through the
// joint frame's origin, as the joint does.
struct UrdfArm::Links {
  // The arm's data rather than the arm: one load less per use in the walk's loop.
  const UrdfArmJoint* joints;
  const Pose* origins;
  const Pose& tip;
  int count;

  explicit Links(const UrdfArm& arm)
      : joints(arm.geometry_.joints.data()),
        origins(arm.origins_.data()),
        tip(arm.tip_),
        count(arm.num_joints()) {}
  int size() const { return count; }
  int tool_index() const { return joint_index(count); }
  void to_tip(Pose& frame) const { frame = compose(frame, tip); }

  template <class Record>
  void advance(int i, const ParamsRef& params, double q, Pose& frame, Record& record) const {
    const UrdfArmJoint& joint = joints[i];
    const int c = joint_index(i);
    const Pose before = compose(frame, origins[i]);
    const FrameBlock error = frame_block(params.segment<6>(c));
    frame = compose(before, error.frame);
    record.parameter_frame(c, before, frame, error.angular_jacobian);
    const Vector3d axis = frame.rotation * joint.axis;
    const bool revolute = is_revolute(joint.type);
    record.joint(i, revolute, axis, frame.translation);
    if (revolute)
      record.parameter_rotation(c + kOffset, axis, frame.translation);
    else
      record.parameter_translation(c + kOffset, axis);
    frame = compose(frame, urdf_joint_motion(joint, q + params[c + kOffset]));
    record.link(i, frame);
  }
};

namespace {

// The tip link's pose: the frame the tool block follows.
struct TipRecord : serial_chain::PoseOnly {
  Pose tip;
  void finish(const Pose& tip_frame, const Pose&) { tip = tip_frame; }
};

}  // namespace

serial_chain::ComplianceLayout UrdfArm::compliance_layout() const {
  return {&compliance_, compliance_index(), has_payload_actuator(), &gravity_params_};
}

void UrdfArm::gravity_chain(const ActuatorsRef& q, GravityChain& chain) const {
  serial_chain::gravity_chain(Links(*this), compliance_layout(), q, chain);
}

void UrdfArm::deflected_joints(const ParamsRef& params, const ActuatorsRef& q, JointVector& joints,
                               DeflectionJacobian* deflection) const {
  serial_chain::deflect(Links(*this), compliance_layout(), params, q, joints, deflection);
}

ForwardKinematicsResult UrdfArm::forward_kinematics(const ParamsRef& params, const ActuatorsRef& q,
                                                    const Pose&,
                                                    const ForwardKinematicsOptions&) const {
  ForwardKinematicsResult result;
  if (!q.allFinite()) {
    result.status = ForwardKinematicsStatus::kInvalidActuators;
    return result;
  }
  result.pose = serial_chain::walk_deflected(Links(*this), compliance_layout(), params, q,
                                             serial_chain::PoseOnly{});
  if (!finite(result.pose)) {
    result.status = ForwardKinematicsStatus::kNonFinite;
    result.pose = Pose{};
  }
  return result;
}

Pose UrdfArm::tip_pose(const ParamsRef& params, const ActuatorsRef& q) const {
  TipRecord record;
  serial_chain::walk_deflected(Links(*this), compliance_layout(), params, q, record);
  return record.tip;
}

void UrdfArm::pose_jacobian_params(const ParamsRef& params, const ActuatorsRef& q, const Pose&,
                                   Eigen::Ref<Matrix6Xd> J_pose_params) const {
  serial_chain::compliant_parameter_columns(Links(*this), compliance_layout(), params, q,
                                            J_pose_params);
}

Pose UrdfArm::joint_jacobian(const ParamsRef& params, const ActuatorsRef& q,
                             Eigen::Ref<Matrix6Xd> J_pose_q) const {
  return serial_chain::compliant_joint_columns(Links(*this), compliance_layout(), params, q,
                                               J_pose_q);
}

InverseKinematicsResult UrdfArm::inverse_kinematics(const ParamsRef& params, const Pose& pose,
                                                    Eigen::Ref<VectorXd> q) const {
  return inverse_kinematics_from(params, pose, home_q_, q);
}

InverseKinematicsResult UrdfArm::inverse_kinematics_from(
    const ParamsRef& params, const Pose& pose, const ActuatorsRef& start, Eigen::Ref<VectorXd> q,
    const SerialInverseKinematicsOptions& options) const {
  if (!params.allFinite()) {
    q = home_q_;
    InverseKinematicsResult result;
    result.status = InverseKinematicsStatus::kNonFinite;
    return result;
  }
  return serial_chain::inverse_kinematics(
      pose, start, q, options,
      [&](const VectorXd& x) {
        return serial_chain::walk_deflected(Links(*this), compliance_layout(), params, x,
                                            serial_chain::PoseOnly{});
      },
      [&](const VectorXd& x, Matrix6Xd& J) { return joint_jacobian(params, x, J); });
}

std::vector<int> UrdfArm::identification_priority() const {
  std::vector<int> priority(parameters().size(), 0);
  for (int j = 0; j < num_joints(); ++j) {
    for (int k = 0; k < 6; ++k) priority[static_cast<std::size_t>(joint_index(j) + k)] = 2;
    priority[static_cast<std::size_t>(joint_index(j) + kOffset)] = 1;
  }
  // Where the data cannot tell a deflection from a geometric error, the geometry keeps it.
  for (int k = 0; k < compliance_.num_parameters(); ++k)
    priority[static_cast<std::size_t>(compliance_index() + k)] = 3;
  return priority;
}

std::vector<int> UrdfArm::non_geometric_parameters() const {
  return compliance_.indices(compliance_index());
}

std::vector<int> urdf_arm_parameter_priority(const MeasurementModel& model) {
  std::vector<int> priority = model.identification_priority();
  if (priority.empty()) priority.assign(static_cast<std::size_t>(model.num_parameters()), 0);
  return priority;
}

void free_what_home_configurations_determine(MeasurementModel& model, double a, double b,
                                             double d) {
  const auto& arm = dynamic_cast<const UrdfArm&>(model.mechanism());
  const VectorXd nominal = model.parameters().nominal_values();
  VectorXd home(arm.num_actuators()), q(arm.num_actuators()), readings(model.num_readings());
  arm.home_actuators(nominal, home);
  auto ws = model.make_workspace();
  const int configurations = 30;
  MatrixXd J(configurations * model.num_readings(), model.num_parameters());
  MatrixXd block(model.num_readings(), model.num_parameters());
  for (int c = 0; c < configurations; ++c) {
    q = home;
    for (int i = 0; i < arm.num_joints(); ++i)
      q[i] = home[i] + arm.actuators()[static_cast<std::size_t>(i)].default_range *
                           std::sin(a * c + b * i + d * c * i);
    Eigen::Ref<MatrixXd> ref(block);
    model.predict(nominal, q, readings, &ref, ws);
    J.middleRows(c * model.num_readings(), model.num_readings()) = block;
  }
  for (int i : identifiable_subset(J, urdf_arm_parameter_priority(model)))
    model.parameters().set_free(model.parameters()[i].name, true);
}

}  // namespace kincal
