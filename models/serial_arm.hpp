#pragma once
// A serial arm: N joints, each revolute (actuator in rad) or prismatic (mm), between a base
// transform and a tool transform:
//
//   T(q) = B  A_1(q_1)  A_2(q_2) ... A_N(q_N)  E
//
// B (base) and E (tool) are frame parameter blocks (x, y, z, rx, ry, rz; pose.hpp). Link i
// takes frame i-1 (z axis = joint i's axis) to frame i (z axis = joint i+1's axis) in one
// of two conventions:
//   standard DH: A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)
//   Hayati:      A_i = Rz(theta_i) Tx(a_i) Rx(alpha_i) Ry(beta_i)
// Hayati's rotation beta about y replaces d, which is undefined (any point of a common
// normal's infinitely many) when joint i's and joint i+1's axes are parallel: a tiny tilt of
// nominally parallel axes would make DH's d_i jump by metres, and its identification
// Jacobian loses rank. Use Hayati for links whose two axes are (nominally) parallel.
// The joint value adds to the offset: theta_i + q_i for a revolute joint, d_i + q_i for a
// prismatic one (prismatic joints are always DH: their variable is d).
//
// Parameters, in order: base.{x,y,z,rx,ry,rz}, then per joint <name>.{a, alpha, d, theta}
// (DH) or <name>.{a, alpha, beta, theta} (Hayati), then tool.{x,y,z,rx,ry,rz}; lengths in
// mm, angles in rad. Forward kinematics is closed form, J_pose_params analytic (every
// parameter is an elementary rotation or translation somewhere in the chain), inverse
// kinematics numerical (damped least squares from the home joints); the walk from base to
// tool and the inverse kinematics are those of every serial chain (serial_chain.hpp), this
// arm gives its links. See docs/theory.md.
//
// Optionally (geometry.compliance, models/joint_compliance.hpp) each joint deflects under
// gravity and the payload, as the urdf-arm's do: the compliance parameters after the tool
// frame's, a payload actuator after the joints when its mass is a column, link masses'
// centres in DH frame i (the frame after link i, as manufacturers' tables give them). The
// torques are taken on the arm's geometry as constructed (the model file's values).

#include <string>
#include <vector>

#include "kincal/framework/kinematics/mechanism.hpp"
#include "kincal/models/joint_compliance.hpp"
#include "kincal/models/serial_chain.hpp"

namespace kincal::serial_chain {
struct ComplianceLayout;
}

namespace kincal {

class ModelRegistry;

enum class JointType { kRevolute, kPrismatic };
enum class LinkConvention { kDh, kHayati };

const char* to_string(JointType type);
const char* to_string(LinkConvention convention);

/// One joint and the link that follows it (A_i above). Lengths mm, angles rad.
struct SerialJoint {
  std::string name;  ///< actuator column and parameter prefix, e.g. "joint1"
  JointType type = JointType::kRevolute;
  LinkConvention convention = LinkConvention::kDh;
  double a = 0;
  double alpha = 0;
  double d = 0;      ///< DH only (offset of a prismatic joint)
  double beta = 0;   ///< Hayati only
  double theta = 0;  ///< offset of a revolute joint; a constant for a prismatic one
  double home = 0;   ///< actuator value at home (rad or mm)
  /// Half-width of the default configuration box (rad or mm); <= 0 or NaN = the default
  /// for the joint type (SerialArm::kDefaultRevoluteRange / kDefaultPrismaticRange).
  double range = 0;
};

/// Base and tool are frame parameter blocks [x, y, z, rx, ry, rz] (mm, rad;
/// frame_from_parameters), kept as given so that model files round-trip digit for digit.
struct SerialArmGeometry {
  Vector6d base = Vector6d::Zero();
  std::vector<SerialJoint> joints;
  Vector6d tool = Vector6d::Zero();
  /// Joint compliance under gravity; off unless enabled.
  ComplianceSpec compliance;
};

class SerialArm final : public Mechanism {
 public:
  /// +-0.5 rad (about 29 degrees) per revolute joint around home: wide enough that the
  /// joints' parameters are seen from many directions (the presets' condition numbers are
  /// about 400, against 1500-2100 at +-0.25 rad), small enough that a home well away from the
  /// singularities (elbow stretched, wrist axes aligned) keeps the whole box regular and
  /// inverse kinematics from home converges everywhere in it. See docs/theory.md.
  static constexpr double kDefaultRevoluteRange = 0.5;
  /// +-50 mm per prismatic joint.
  static constexpr double kDefaultPrismaticRange = 50.0;
  static constexpr int kFrameParameters = 6;
  static constexpr int kLinkParameters = 4;

  /// Throws std::invalid_argument on a geometry it cannot represent (no joint, duplicate or
  /// reserved names, a Hayati prismatic joint, non-finite values). All parameters fixed.
  explicit SerialArm(SerialArmGeometry geometry);

  std::string type() const override { return "serial-arm"; }
  const std::vector<Actuator>& actuators() const override { return actuators_; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  const Pose& home_pose() const override { return home_pose_; }
  /// Closed form: one pose per joint vector, whatever the start.
  const SerialArmGeometry& nominal_geometry() const { return geometry_; }
  int num_joints() const { return static_cast<int>(geometry_.joints.size()); }
  const JointCompliance& compliance() const { return compliance_; }
  bool has_compliance() const { return compliance_.enabled(); }
  bool has_payload_actuator() const {
    return compliance_.enabled() && geometry_.compliance.payload_column;
  }
  /// The first compliance parameter (after the tool frame's six).
  int compliance_index() const { return tool_index() + kFrameParameters; }
  /// The compliance parameters.
  std::vector<int> non_geometric_parameters() const override;
  /// Where the data cannot tell a deflection from a geometric error, the geometry keeps it
  /// (empty without compliance: no preference).
  std::vector<int> identification_priority() const override;
  /// The nominal chain at q as gravity sees it (models/joint_compliance.hpp).
  void gravity_chain(const ActuatorsRef& q, GravityChain& chain) const;

  /// The home joint values of the model (whatever the parameters).
  InverseKinematicsResult home_actuators(const ParamsRef& params,
                                         Eigen::Ref<VectorXd> q) const override;

  /// Damped least squares from the home joints. kUnreachable when an arm with fewer than
  /// six joints stops at a least-squares minimum away from the pose; kNotConverged when an
  /// arm with six or more stops away from it (a local minimum, or a pose out of reach) or
  /// runs out of iterations. The pose error left is in residual_norm and the reason, and q
  /// holds the closest joint values found (home for non-finite input).
  InverseKinematicsResult inverse_kinematics(const ParamsRef& params, const Pose& pose,
                                             Eigen::Ref<VectorXd> q) const override;
  /// The same from the joint values `start`.
  InverseKinematicsResult inverse_kinematics_from(
      const ParamsRef& params, const Pose& pose, const ActuatorsRef& start, Eigen::Ref<VectorXd> q,
      const SerialInverseKinematicsOptions& options = {}) const;
  InverseKinematicsResult inverse_kinematics_near(const ParamsRef& params, const Pose& pose,
                                                  const ActuatorsRef& start,
                                                  Eigen::Ref<VectorXd> q) const override {
    return inverse_kinematics_from(params, pose, start, q);
  }

  /// Closed form; `start` and `options` are not used. Fails only on non-finite values.
  ForwardKinematicsResult forward_kinematics(
      const ParamsRef& params, const ActuatorsRef& q, const Pose& start,
      const ForwardKinematicsOptions& options = {}) const override;

  void pose_jacobian_params(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
                            Eigen::Ref<Matrix6Xd> J_pose_params) const override;

  /// The geometric Jacobian J_pose_q (6 x N, pose perturbation convention of pose.hpp) and
  /// the pose at q.
  Pose joint_jacobian(const ParamsRef& params, const ActuatorsRef& q,
                      Eigen::Ref<Matrix6Xd> J_pose_q) const;

  /// The geometry stored in a parameter vector (names, types, home and ranges from the
  /// nominal geometry).
  SerialArmGeometry geometry_from(const ParamsRef& params) const;

  static int base_index() { return 0; }
  static int joint_index(int joint) { return kFrameParameters + kLinkParameters * joint; }
  int tool_index() const { return joint_index(num_joints()); }
  /// Within a joint's block: a, alpha, d or beta, theta.
  static constexpr int kA = 0, kAlpha = 1, kDOrBeta = 2, kTheta = 3;

 private:
  /// The DH/Hayati links, for serial_chain::walk (models/serial_arm.cpp).
  struct Links;
  serial_chain::ComplianceLayout compliance_layout() const;

  SerialArmGeometry geometry_;
  JointCompliance compliance_;
  VectorXd gravity_params_;  ///< the geometry as constructed, the base at identity
  std::vector<Actuator> actuators_;
  std::vector<Parameter> parameters_;
  Pose home_pose_;
  VectorXd home_q_;
};

/// The nominal parameter vector of a geometry, in SerialArm's layout.
VectorXd serial_arm_parameters(const SerialArmGeometry& geometry);

/// Registers the serial-arm type (model-file reader/writer), the point- and pose-tracker
/// sensor types and the presets puma560 and ur5.
void register_serial_arm(ModelRegistry& registry);

}  // namespace kincal
