#include "kincal/models/serial_arm.hpp"

#include "kincal/models/compliant_chain.hpp"

#include <cmath>
#include <set>
#include <stdexcept>

namespace kincal {

using serial_chain::add_frame_parameters;

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
  if (geometry_.compliance.enabled) {
    std::vector<std::string> joint_names;
    std::vector<bool> revolute;
    for (const SerialJoint& j : joints) {
      joint_names.push_back(j.name);
      revolute.push_back(j.type == JointType::kRevolute);
    }
    compliance_ = JointCompliance(geometry_.compliance, joint_names, revolute);
    geometry_.compliance = compliance_.spec();
    // Gravity's chain: the geometry as constructed, in the base's coordinates.
    gravity_params_ = serial_arm_parameters(geometry_).head(parameters_.size());
    gravity_params_.head<6>().setZero();
    VectorXd home(num_joints());
    for (int i = 0; i < num_joints(); ++i) home[i] = joints[static_cast<std::size_t>(i)].home;
    GravityChain at_home;
    gravity_chain(home, at_home);
    compliance_.scale_tolerances(at_home);
    compliance_.add_to(parameters_, actuators_, names, "serial arm");
  }

  home_q_.resize(num_actuators());
  for (int i = 0; i < num_joints(); ++i) home_q_[i] = joints[i].home;
  if (has_payload_actuator()) home_q_[num_joints()] = 0.5 * geometry_.compliance.payload_max;
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
  if (!geometry.compliance.enabled) return p;
  std::vector<std::string> names;
  std::vector<bool> revolute;
  for (const SerialJoint& j : geometry.joints) {
    names.push_back(j.name);
    revolute.push_back(j.type == JointType::kRevolute);
  }
  return JointCompliance(geometry.compliance, names, revolute).appended_to(p);
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
  if (has_compliance())
    g.compliance =
        compliance_.spec_with(params.segment(compliance_index(), compliance_.num_parameters()));
  return g;
}

InverseKinematicsResult SerialArm::home_actuators(const ParamsRef&, Eigen::Ref<VectorXd> q) const {
  q = home_q_;
  return {};
}

// Link i for serial_chain::walk: A_i(q_i) and its parameters' elementary motions. Every
// parameter is a rotation or translation about an axis the walk passes: theta turns about
// frame i-1's z axis through its origin (as a revolute joint does), d slides along it (as a
// prismatic joint does), a slides along the x axis after Rz(theta), alpha turns about that x
// axis and beta about the final y axis, both through the new origin (Rx leaves x fixed, Ry
// leaves y fixed).
struct SerialArm::Links {
  // The arm's data rather than the arm: one load less per use in the walk's loop.
  const SerialJoint* joints;
  int count;

  explicit Links(const SerialArm& arm)
      : joints(arm.geometry_.joints.data()), count(arm.num_joints()) {}
  int size() const { return count; }
  int tool_index() const { return joint_index(count); }
  void to_tip(Pose&) const {}

  template <class Record>
  void advance(int i, const ParamsRef& params, double q, Pose& frame, Record& record) const {
    const SerialJoint& joint = joints[i];
    const int c = joint_index(i);
    const auto link = params.segment<4>(c);
    const bool revolute = joint.type == JointType::kRevolute;
    const bool dh = joint.convention == LinkConvention::kDh;
    const double theta = link[kTheta] + (revolute ? q : 0.0);
    const Vector3d z_prev = frame.rotation.col(2), o_prev = frame.translation;
    rotate_z(frame.rotation, std::cos(theta), std::sin(theta));
    const Vector3d x_new = frame.rotation.col(0);  // x after Rz(theta): a's and alpha's axis
    if (dh) {
      const double d = link[kDOrBeta] + (revolute ? 0.0 : q);
      frame.translation += d * z_prev + link[kA] * x_new;
      rotate_x(frame.rotation, std::cos(link[kAlpha]), std::sin(link[kAlpha]));
    } else {
      frame.translation += link[kA] * x_new;
      rotate_x(frame.rotation, std::cos(link[kAlpha]), std::sin(link[kAlpha]));
      rotate_y(frame.rotation, std::cos(link[kDOrBeta]), std::sin(link[kDOrBeta]));
    }
    record.joint(i, revolute, z_prev, o_prev);
    record.parameter_translation(c + kA, x_new);
    record.parameter_rotation(c + kAlpha, x_new, frame.translation);
    if (dh)
      record.parameter_translation(c + kDOrBeta, z_prev);
    else
      record.parameter_rotation(c + kDOrBeta, frame.rotation.col(1), frame.translation);
    record.parameter_rotation(c + kTheta, z_prev, o_prev);
    record.link(i, frame);
  }
};

ForwardKinematicsResult SerialArm::forward_kinematics(const ParamsRef& params,
                                                      const ActuatorsRef& q, const Pose&,
                                                      const ForwardKinematicsOptions&) const {
  ForwardKinematicsResult result;
  if (!q.allFinite()) {
    result.status = ForwardKinematicsStatus::kInvalidActuators;
    return result;
  }
  result.pose = serial_chain::walk_deflected(Links(*this), compliance_layout(), params, q,
                                             serial_chain::PoseOnly{});
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
  serial_chain::compliant_parameter_columns(Links(*this), compliance_layout(), params, q,
                                            J_pose_params);
}

Pose SerialArm::joint_jacobian(const ParamsRef& params, const ActuatorsRef& q,
                               Eigen::Ref<Matrix6Xd> J_pose_q) const {
  return serial_chain::compliant_joint_columns(Links(*this), compliance_layout(), params, q,
                                               J_pose_q);
}

serial_chain::ComplianceLayout SerialArm::compliance_layout() const {
  return {&compliance_, compliance_index(), has_payload_actuator(), &gravity_params_};
}

void SerialArm::gravity_chain(const ActuatorsRef& q, GravityChain& chain) const {
  serial_chain::gravity_chain(Links(*this), compliance_layout(), q, chain);
}

std::vector<int> SerialArm::non_geometric_parameters() const {
  return compliance_.indices(compliance_index());
}

std::vector<int> SerialArm::identification_priority() const {
  if (!has_compliance()) return {};
  std::vector<int> priority(parameters_.size(), 0);
  for (int k : non_geometric_parameters()) priority[static_cast<std::size_t>(k)] = 3;
  return priority;
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
      pose, start, q, options,
      [&](const VectorXd& x) {
        return serial_chain::walk_deflected(Links(*this), compliance_layout(), params, x,
                                            serial_chain::PoseOnly{});
      },
      [&](const VectorXd& x, Matrix6Xd& J) { return joint_jacobian(params, x, J); });
}

}  // namespace kincal
