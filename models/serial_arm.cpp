#include "kincal/models/serial_arm.hpp"

#include <cmath>
#include <set>
#include <stdexcept>

namespace kincal {

using serial_chain::add_frame_parameters;
using serial_chain::finish_columns;
using serial_chain::frame_block_columns;
using serial_chain::rotation_column;
using serial_chain::translation_column;

const char* to_string(JointType type) {
  return type == JointType::kRevolute ? "revolute" : "prismatic";
}

const char* to_string(LinkConvention convention) {
  return convention == LinkConvention::kDh ? "dh" : "hayati";
}

namespace {

// R * Rz(angle), R * Rx(angle), R * Ry(angle), column by column (no 3x3 product).
void rotate_z(Matrix3d& R, double c, double s) {
  const Vector3d x = R.col(0), y = R.col(1);
  R.col(0) = c * x + s * y;
  R.col(1) = c * y - s * x;
}
void rotate_x(Matrix3d& R, double c, double s) {
  const Vector3d y = R.col(1), z = R.col(2);
  R.col(1) = c * y + s * z;
  R.col(2) = c * z - s * y;
}
void rotate_y(Matrix3d& R, double c, double s) {
  const Vector3d x = R.col(0), z = R.col(2);
  R.col(0) = c * x - s * z;
  R.col(2) = s * x + c * z;
}

}  // namespace

SerialArm::SerialArm(SerialArmGeometry geometry) : geometry_(std::move(geometry)) {
  const auto& joints = geometry_.joints;
  if (joints.empty()) throw std::invalid_argument("a serial arm needs at least one joint");
  std::set<std::string> names;
  add_frame_parameters(parameters_, "base", geometry_.base);
  for (std::size_t i = 0; i < joints.size(); ++i) {
    SerialJoint& j = geometry_.joints[i];
    const std::string where = "serial arm joint " + std::to_string(i + 1) + " ('" + j.name + "')";
    if (j.name.empty() || j.name == "base" || j.name == "tool" || !names.insert(j.name).second)
      throw std::invalid_argument(where + ": expected a unique name other than 'base' and 'tool'");
    if (j.type == JointType::kPrismatic && j.convention == LinkConvention::kHayati)
      throw std::invalid_argument(
          where +
          ": a prismatic joint's variable is d, which Hayati's convention removes; "
          "expected convention dh");
    for (double v : {j.a, j.alpha, j.d, j.beta, j.theta, j.home})
      if (!std::isfinite(v)) throw std::invalid_argument(where + ": non-finite value");
    const bool revolute = j.type == JointType::kRevolute;
    if (!(j.range > 0) || !std::isfinite(j.range))
      j.range = revolute ? kDefaultRevoluteRange : kDefaultPrismaticRange;
    const bool dh = j.convention == LinkConvention::kDh;
    parameters_.push_back({j.name + ".a", j.a, "mm", false});
    parameters_.push_back({j.name + ".alpha", j.alpha, "rad", false});
    parameters_.push_back(dh ? Parameter{j.name + ".d", j.d, "mm", false}
                             : Parameter{j.name + ".beta", j.beta, "rad", false});
    parameters_.push_back({j.name + ".theta", j.theta, "rad", false});
    actuators_.push_back({j.name, revolute ? "rad" : "mm", j.range});
  }
  add_frame_parameters(parameters_, "tool", geometry_.tool);
  if (!geometry_.base.allFinite() || !geometry_.tool.allFinite())
    throw std::invalid_argument("serial arm: non-finite base or tool frame");

  home_q_.resize(num_joints());
  for (int i = 0; i < num_joints(); ++i) home_q_[i] = joints[i].home;
  const VectorXd nominal = serial_arm_parameters(geometry_);
  const ForwardKinematicsResult home = forward_kinematics(nominal, home_q_, Pose{});
  if (!home.ok()) throw std::invalid_argument("serial arm: home pose " + home.describe());
  home_pose_ = home.pose;
}

VectorXd serial_arm_parameters(const SerialArmGeometry& geometry) {
  const int n = static_cast<int>(geometry.joints.size());
  VectorXd p(SerialArm::kFrameParameters * 2 + SerialArm::kLinkParameters * n);
  p.head<6>() = geometry.base;
  for (int i = 0; i < n; ++i) {
    const SerialJoint& j = geometry.joints[i];
    p.segment<4>(SerialArm::joint_index(i)) << j.a, j.alpha,
        j.convention == LinkConvention::kDh ? j.d : j.beta, j.theta;
  }
  p.tail<6>() = geometry.tool;
  return p;
}

SerialArmGeometry SerialArm::geometry_from(const ParamsRef& params) const {
  SerialArmGeometry g = geometry_;
  g.base = params.segment<6>(base_index());
  for (int i = 0; i < num_joints(); ++i) {
    SerialJoint& j = g.joints[i];
    const auto link = params.segment<4>(joint_index(i));
    j.a = link[kA];
    j.alpha = link[kAlpha];
    (j.convention == LinkConvention::kDh ? j.d : j.beta) = link[kDOrBeta];
    j.theta = link[kTheta];
  }
  g.tool = params.segment<6>(tool_index());
  return g;
}

InverseKinematicsResult SerialArm::home_actuators(const ParamsRef&, Eigen::Ref<VectorXd> q) const {
  q = home_q_;
  return {};
}

// One pass from base to tool: the end pose and, when asked for, J_pose_params (columns in
// the parameter layout) and J_pose_q. Every parameter is an elementary motion somewhere in
// the chain: a translation along a unit axis u moves the end by u (no rotation); a rotation
// about u through o turns it by u and moves it by u x (t_end - o).
template <class Visit>
Pose SerialArm::walk_chain(const ParamsRef& params, const ActuatorsRef& q, Visit&& visit) const {
  const auto base = params.segment<6>(base_index());
  Pose frame = frame_from_parameters(base);
  visit.base(frame, base.tail<3>());
  for (int i = 0; i < num_joints(); ++i) {
    const SerialJoint& joint = geometry_.joints[i];
    const auto link = params.segment<4>(joint_index(i));
    const bool revolute = joint.type == JointType::kRevolute;
    const double theta = link[kTheta] + (revolute ? q[i] : 0.0);
    const Vector3d z_prev = frame.rotation.col(2), o_prev = frame.translation;
    rotate_z(frame.rotation, std::cos(theta), std::sin(theta));
    const Vector3d x_new = frame.rotation.col(0);  // x after Rz(theta): a's and alpha's axis
    if (joint.convention == LinkConvention::kDh) {
      const double d = link[kDOrBeta] + (revolute ? 0.0 : q[i]);
      frame.translation += d * z_prev + link[kA] * x_new;
      rotate_x(frame.rotation, std::cos(link[kAlpha]), std::sin(link[kAlpha]));
    } else {
      frame.translation += link[kA] * x_new;
      rotate_x(frame.rotation, std::cos(link[kAlpha]), std::sin(link[kAlpha]));
      rotate_y(frame.rotation, std::cos(link[kDOrBeta]), std::sin(link[kDOrBeta]));
    }
    visit.link(i, revolute, joint.convention, z_prev, o_prev, x_new, frame);
  }
  const auto tool = params.segment<6>(tool_index());
  const Pose tool_frame = frame_from_parameters(tool);
  Pose end;
  end.rotation = frame.rotation * tool_frame.rotation;
  end.translation = frame.translation + frame.rotation * tool_frame.translation;
  visit.tool(frame, end, tool.tail<3>());
  return end;
}

namespace {

struct NoVisit {
  void base(const Pose&, const Vector3d&) {}
  void link(int, bool, LinkConvention, const Vector3d&, const Vector3d&, const Vector3d&,
            const Pose&) {}
  void tool(const Pose&, const Pose&, const Vector3d&) {}
};

// Fills J_pose_params in the moment form (see rotation_column); finish_columns completes it.
struct ParamsJacobianVisit {
  Eigen::Ref<Matrix6Xd>& J;
  int tool_column;

  void base(const Pose& frame, const Vector3d& angles) {
    frame_block_columns(J.middleCols<6>(SerialArm::base_index()), Pose{}, frame, angles);
  }
  void link(int i, bool, LinkConvention convention, const Vector3d& z_prev, const Vector3d& o_prev,
            const Vector3d& x_new, const Pose& frame) {
    const int c = SerialArm::joint_index(i);
    translation_column(J.col(c + SerialArm::kA), x_new);
    // alpha turns about x_new through the new origin (Rx leaves x fixed).
    rotation_column(J.col(c + SerialArm::kAlpha), x_new, frame.translation);
    if (convention == LinkConvention::kDh)
      translation_column(J.col(c + SerialArm::kDOrBeta), z_prev);
    else  // beta turns about the final y axis (Ry leaves y fixed) through the new origin.
      rotation_column(J.col(c + SerialArm::kDOrBeta), frame.rotation.col(1), frame.translation);
    rotation_column(J.col(c + SerialArm::kTheta), z_prev, o_prev);
  }
  void tool(const Pose& frame, const Pose& end, const Vector3d& angles) {
    // The tool's rotation turns the end about its own origin: no translation.
    frame_block_columns(J.middleCols<6>(tool_column), frame, end, angles);
  }
};

// J_pose_q: a revolute joint turns about its axis z_prev through o_prev, a prismatic one
// translates along it.
struct JointJacobianVisit {
  Eigen::Ref<Matrix6Xd>& J;

  void base(const Pose&, const Vector3d&) {}
  void link(int i, bool revolute, LinkConvention, const Vector3d& z_prev, const Vector3d& o_prev,
            const Vector3d&, const Pose&) {
    if (revolute)
      rotation_column(J.col(i), z_prev, o_prev);
    else
      translation_column(J.col(i), z_prev);
  }
  void tool(const Pose&, const Pose&, const Vector3d&) {}
};

}  // namespace

ForwardKinematicsResult SerialArm::forward_kinematics(const ParamsRef& params,
                                                      const ActuatorsRef& q, const Pose&,
                                                      const ForwardKinematicsOptions&) const {
  ForwardKinematicsResult result;
  if (!q.allFinite()) {
    result.status = ForwardKinematicsStatus::kInvalidActuators;
    return result;
  }
  result.pose = walk_chain(params, q, NoVisit{});
  if (!result.pose.rotation.allFinite() || !result.pose.translation.allFinite()) {
    result.status = ForwardKinematicsStatus::kNonFinite;
    result.pose = Pose{};
  }
  return result;
}

void SerialArm::pose_jacobian_params(const ParamsRef& params, const ActuatorsRef& q, const Pose&,
                                     Eigen::Ref<Matrix6Xd> J_pose_params) const {
  // The end pose is recomputed rather than taken from the argument: the columns must be
  // those of (params, q) whatever pose the caller holds.
  const Pose end = walk_chain(params, q, ParamsJacobianVisit{J_pose_params, tool_index()});
  finish_columns(J_pose_params, end.translation);
}

Pose SerialArm::joint_jacobian(const ParamsRef& params, const ActuatorsRef& q,
                               Eigen::Ref<Matrix6Xd> J_pose_q) const {
  const Pose end = walk_chain(params, q, JointJacobianVisit{J_pose_q});
  finish_columns(J_pose_q, end.translation);
  return end;
}

InverseKinematicsResult SerialArm::inverse_kinematics(const ParamsRef& params, const Pose& pose,
                                                      Eigen::Ref<VectorXd> q) const {
  return inverse_kinematics_from(params, pose, home_q_, q);
}

InverseKinematicsResult SerialArm::inverse_kinematics_from(
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

}  // namespace kincal
