#include "kincal/models/urdf_arm.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <set>
#include <stdexcept>

#include "kincal/framework/analysis/identifiability.hpp"

namespace kincal {

using serial_chain::add_frame_parameters;
using serial_chain::finish_columns;
using serial_chain::frame_block_columns;
using serial_chain::rotation_column;
using serial_chain::translation_column;

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
    origins_.push_back(frame_from_parameters(j.origin));
  }
  tip_ = frame_from_parameters(geometry_.tip);
  add_frame_parameters(parameters_, "tool", geometry_.tool);
  if (!geometry_.base.allFinite() || !geometry_.tool.allFinite() || !geometry_.tip.allFinite())
    throw std::invalid_argument("URDF arm: non-finite base, tip or tool frame");

  home_q_.resize(num_joints());
  for (int i = 0; i < num_joints(); ++i) home_q_[i] = joints[i].home;
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
  return p;
}

UrdfArmGeometry UrdfArm::geometry_from(const ParamsRef& params) const {
  UrdfArmGeometry g = geometry_;
  g.base = params.segment<6>(base_index());
  for (int i = 0; i < num_joints(); ++i) {
    g.joints[i].origin_error = params.segment<6>(joint_index(i));
    g.joints[i].offset = params[joint_index(i) + kOffset];
  }
  g.tool = params.segment<6>(tool_index());
  return g;
}

InverseKinematicsResult UrdfArm::home_actuators(const ParamsRef&, Eigen::Ref<VectorXd> q) const {
  q = home_q_;
  return {};
}

// One pass from base to tool. Every parameter is an elementary motion somewhere in the
// chain: a translation along a unit axis u moves the end by u; a rotation about u through o
// turns it by u and moves it by u x (t_end - o).
template <class Visit>
Pose UrdfArm::walk_chain(const ParamsRef& params, const ActuatorsRef& q, Visit&& visit) const {
  const auto base = params.segment<6>(base_index());
  Pose frame = frame_from_parameters(base);
  visit.base(frame, base.tail<3>());
  for (int i = 0; i < num_joints(); ++i) {
    const UrdfArmJoint& joint = geometry_.joints[i];
    const Pose before = compose(frame, origins_[i]);
    const auto error = params.segment<6>(joint_index(i));
    frame = compose(before, frame_from_parameters(error));
    visit.origin_error(i, before, frame, error.tail<3>());
    const Vector3d axis = frame.rotation * joint.axis;
    const bool revolute = is_revolute(joint.type);
    visit.joint(i, revolute, axis, frame.translation);
    frame = compose(frame, urdf_joint_motion(joint, q[i] + params[joint_index(i) + kOffset]));
  }
  frame = compose(frame, tip_);
  const auto tool = params.segment<6>(tool_index());
  const Pose end = compose(frame, frame_from_parameters(tool));
  visit.tool(frame, end, tool.tail<3>());
  return end;
}

namespace {

struct NoVisit {
  void base(const Pose&, const Vector3d&) {}
  void origin_error(int, const Pose&, const Pose&, const Vector3d&) {}
  void joint(int, bool, const Vector3d&, const Vector3d&) {}
  void tool(const Pose&, const Pose&, const Vector3d&) {}
};

struct TipVisit : NoVisit {
  Pose* tip;
  void tool(const Pose& frame, const Pose&, const Vector3d&) { *tip = frame; }
};

struct ParamsJacobianVisit {
  Eigen::Ref<Matrix6Xd>& J;
  int tool_column;

  void base(const Pose& frame, const Vector3d& angles) {
    frame_block_columns(J.middleCols<6>(UrdfArm::base_index()), Pose{}, frame, angles);
  }
  void origin_error(int i, const Pose& before, const Pose& after, const Vector3d& angles) {
    frame_block_columns(J.middleCols<6>(UrdfArm::joint_index(i)), before, after, angles);
  }
  void joint(int i, bool revolute, const Vector3d& axis, const Vector3d& origin) {
    auto column = J.col(UrdfArm::joint_index(i) + UrdfArm::kOffset);
    if (revolute)
      rotation_column(column, axis, origin);
    else
      translation_column(column, axis);
  }
  void tool(const Pose& frame, const Pose& end, const Vector3d& angles) {
    frame_block_columns(J.middleCols<6>(tool_column), frame, end, angles);
  }
};

struct JointJacobianVisit : NoVisit {
  Eigen::Ref<Matrix6Xd>& J;
  explicit JointJacobianVisit(Eigen::Ref<Matrix6Xd>& j) : J(j) {}
  void joint(int i, bool revolute, const Vector3d& axis, const Vector3d& origin) {
    if (revolute)
      rotation_column(J.col(i), axis, origin);
    else
      translation_column(J.col(i), axis);
  }
};

}  // namespace

ForwardKinematicsResult UrdfArm::forward_kinematics(const ParamsRef& params, const ActuatorsRef& q,
                                                    const Pose&,
                                                    const ForwardKinematicsOptions&) const {
  ForwardKinematicsResult result;
  if (!q.allFinite()) {
    result.status = ForwardKinematicsStatus::kInvalidActuators;
    return result;
  }
  result.pose = walk_chain(params, q, NoVisit{});
  if (!finite(result.pose)) {
    result.status = ForwardKinematicsStatus::kNonFinite;
    result.pose = Pose{};
  }
  return result;
}

Pose UrdfArm::tip_pose(const ParamsRef& params, const ActuatorsRef& q) const {
  Pose tip;
  TipVisit visit;
  visit.tip = &tip;
  walk_chain(params, q, visit);
  return tip;
}

void UrdfArm::pose_jacobian_params(const ParamsRef& params, const ActuatorsRef& q, const Pose&,
                                   Eigen::Ref<Matrix6Xd> J_pose_params) const {
  const Pose end = walk_chain(params, q, ParamsJacobianVisit{J_pose_params, tool_index()});
  finish_columns(J_pose_params, end.translation);
}

Pose UrdfArm::joint_jacobian(const ParamsRef& params, const ActuatorsRef& q,
                             Eigen::Ref<Matrix6Xd> J_pose_q) const {
  const Pose end = walk_chain(params, q, JointJacobianVisit(J_pose_q));
  finish_columns(J_pose_q, end.translation);
  return end;
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
      pose, start, q, options, [&](const VectorXd& x) { return walk_chain(params, x, NoVisit{}); },
      [&](const VectorXd& x, Matrix6Xd& J) { return joint_jacobian(params, x, J); });
}

std::vector<int> UrdfArm::identification_priority() const {
  std::vector<int> priority(parameters().size(), 0);
  for (int j = 0; j < num_joints(); ++j) {
    for (int k = 0; k < 6; ++k) priority[static_cast<std::size_t>(joint_index(j) + k)] = 2;
    priority[static_cast<std::size_t>(joint_index(j) + kOffset)] = 1;
  }
  return priority;
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
  VectorXd home(arm.num_joints()), q(arm.num_joints()), readings(model.num_readings());
  arm.home_actuators(nominal, home);
  auto ws = model.make_workspace();
  const int configurations = 30;
  MatrixXd J(configurations * model.num_readings(), model.num_parameters());
  MatrixXd block(model.num_readings(), model.num_parameters());
  for (int c = 0; c < configurations; ++c) {
    for (int i = 0; i < q.size(); ++i)
      q[i] = home[i] + UrdfArm::kDefaultRevoluteRange * std::sin(a * c + b * i + d * c * i);
    Eigen::Ref<MatrixXd> ref(block);
    model.predict(nominal, q, readings, &ref, ws);
    J.middleRows(c * model.num_readings(), model.num_readings()) = block;
  }
  for (int i : identifiable_subset(J, urdf_arm_parameter_priority(model)))
    model.parameters().set_free(model.parameters()[i].name, true);
}

}  // namespace kincal
