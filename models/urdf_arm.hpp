#pragma once
// A serial arm imported from a URDF: the chain of joints from a base link to a tip link, with
// the URDF's joint origins and axes as nominal geometry and an error model that has no
// singular parameter set whatever the axes' arrangement:
//
//   T(q) = B  prod_i [ C_i  E_i  M_i(q_i + o_i) ]  C_tip  T_tool
//
//   B       the base frame (6 parameters base.*): the robot's base link in the frame the
//           measurements are taken in
//   C_i     joint i's URDF origin, composed with the origins of the fixed joints between the
//           previous moving joint and joint i (constant, not a parameter)
//   E_i     joint i's origin error (6 parameters <joint>.origin.{x,y,z,rx,ry,rz}, nominally 0):
//           a small rigid motion of joint i's frame, in that frame's axes
//   M_i     the joint's motion about (revolute, continuous) or along (prismatic) its unit
//           axis a_i (joint frame) by q_i plus the joint offset o_i (<joint>.offset, rad or mm)
//   C_tip   the fixed joints from the last moving joint's child link to the tip link
//   T_tool  the tool frame (6 parameters tool.*) on the tip link: the measured point or frame
//
// Optionally (geometry.compliance, models/joint_compliance.hpp) each joint deflects under
// gravity and the payload: q_i + o_i becomes q_i + delta_i(q) + o_i, delta_i = c_i tau_i(q),
// with the compliance parameters after the tool frame's (so that a model without compliance
// keeps its layout) and, when the payload's mass is a measurement column, an actuator
// "payload" (kg) after the joints.
//
// Each E_i is a full 6-DOF frame about the nominal origin, so every geometric error of the
// chain is representable and the parametrisation is regular at the nominal for any axes
// (no DH-style jump when axes are parallel). It is redundant: a revolute joint's rotation
// about its own axis duplicates its offset, a translation along it the next origin error,
// and so on. The redundancy is resolved for the data at hand (QR with column pivoting on the
// scaled identification Jacobian; kincal calibrate); docs/theory.md derives it.
// Lengths mm, angles rad. Forward kinematics closed form, J_pose_params analytic, inverse
// kinematics damped least squares from the home joints; the walk from base to tool and the
// inverse kinematics are those of every serial chain (serial_chain.hpp), this arm gives its
// links.

#include <string>
#include <vector>

#include <memory>

#include "kincal/framework/kinematics/measurement_model.hpp"
#include "kincal/framework/kinematics/mechanism.hpp"
#include "kincal/models/joint_compliance.hpp"
#include "kincal/models/serial_chain.hpp"

namespace kincal::serial_chain {
struct ComplianceLayout;
}

namespace kincal {

class ModelRegistry;

enum class UrdfJointType { kRevolute, kContinuous, kPrismatic };

const char* to_string(UrdfJointType type);

/// One moving joint of the chain. Lengths mm, angles rad.
struct UrdfArmJoint {
  std::string name;  ///< the URDF joint's name: actuator column and parameter prefix
  UrdfJointType type = UrdfJointType::kRevolute;
  /// C_i (fixed joints before it folded in) as [x, y, z, rx, ry, rz] (frame_from_parameters:
  /// URDF's xyz and rpy, in mm), kept as given so that model files round-trip digit for digit.
  Vector6d origin = Vector6d::Zero();
  Vector3d axis = Vector3d::UnitZ();         ///< unit, in the joint frame
  Vector6d origin_error = Vector6d::Zero();  ///< E_i as [x, y, z, rx, ry, rz]
  double offset = 0;                         ///< o_i (rad or mm)
  /// URDF limits in the joint's unit; NaN for a continuous joint.
  double lower = 0, upper = 0;
  double home = 0;   ///< actuator value at home
  double range = 0;  ///< half-width of the default configuration box; <= 0: the default
};

struct UrdfArmGeometry {
  std::string base_link, tip_link;
  Vector6d base = Vector6d::Zero();
  std::vector<UrdfArmJoint> joints;
  Vector6d tip = Vector6d::Zero();  ///< C_tip, as origin
  Vector6d tool = Vector6d::Zero();
  /// Joint compliance under gravity; off unless enabled.
  ComplianceSpec compliance;
  /// The URDF the geometry was read from, kept so that an export can re-emit the user's own
  /// robot description (names, limits, inertials, meshes) with the corrections.
  std::string urdf_file, urdf_text;
};

class UrdfArm final : public Mechanism {
 public:
  static constexpr double kDefaultRevoluteRange = 0.5;
  static constexpr double kDefaultPrismaticRange = 50.0;
  static constexpr int kFrameParameters = 6;
  static constexpr int kJointParameters = 7;  ///< origin error (6) + offset

  /// Throws std::invalid_argument on a geometry it cannot represent (no joint, duplicate or
  /// reserved names, a zero axis, non-finite values). All parameters fixed.
  explicit UrdfArm(UrdfArmGeometry geometry);

  std::string type() const override { return "urdf-arm"; }
  const std::vector<Actuator>& actuators() const override { return actuators_; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  const Pose& home_pose() const override { return home_pose_; }
  const UrdfArmGeometry& nominal_geometry() const { return geometry_; }
  int num_joints() const { return static_cast<int>(geometry_.joints.size()); }
  /// The joint compliance model (enabled() false when the arm has none).
  const JointCompliance& compliance() const { return compliance_; }
  bool has_compliance() const { return compliance_.enabled(); }
  /// Whether the payload's mass is an actuator (the last, after the joints).
  bool has_payload_actuator() const {
    return compliance_.enabled() && geometry_.compliance.payload_column;
  }

  InverseKinematicsResult home_actuators(const ParamsRef& params,
                                         Eigen::Ref<VectorXd> q) const override;
  /// From home (serial_chain::inverse_kinematics): an unreachable pose is a status with a
  /// reason, q the closest joint values found.
  InverseKinematicsResult inverse_kinematics(const ParamsRef& params, const Pose& pose,
                                             Eigen::Ref<VectorXd> q) const override;
  /// The same from the joint values `start`: the solution nearest a configuration the robot
  /// is in, where several reach the pose.
  InverseKinematicsResult inverse_kinematics_from(
      const ParamsRef& params, const Pose& pose, const ActuatorsRef& start, Eigen::Ref<VectorXd> q,
      const SerialInverseKinematicsOptions& options = {}) const;
  InverseKinematicsResult inverse_kinematics_near(const ParamsRef& params, const Pose& pose,
                                                  const ActuatorsRef& start,
                                                  Eigen::Ref<VectorXd> q) const override {
    return inverse_kinematics_from(params, pose, start, q);
  }
  ForwardKinematicsResult forward_kinematics(
      const ParamsRef& params, const ActuatorsRef& q, const Pose& start,
      const ForwardKinematicsOptions& options = {}) const override;
  void pose_jacobian_params(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
                            Eigen::Ref<Matrix6Xd> J_pose_params) const override;

  /// J_pose_q (6 x actuators) and the pose at q: the joints' columns at the deflected joint
  /// values (the deflection's own change with q, about 1e-3 of it, left out: this Jacobian
  /// steers inverse kinematics; pose_jacobian_actuators is exact), the payload's zero.
  Pose joint_jacobian(const ParamsRef& params, const ActuatorsRef& q,
                      Eigen::Ref<Matrix6Xd> J_pose_q) const;

  /// The joint values after the deflection under gravity, the joints only; `deflection`
  /// (joints x compliance parameters) when given. Only for an arm with compliance.
  void deflected_joints(const ParamsRef& params, const ActuatorsRef& q, JointVector& joints,
                        DeflectionJacobian* deflection = nullptr) const;
  /// The nominal chain at q as gravity sees it (models/joint_compliance.hpp).
  void gravity_chain(const ActuatorsRef& q, GravityChain& chain) const;

  /// A joint's zero turned by pi with the links after it turned back
  /// (models/urdf_arm_symmetry.cpp).
  /// 0 for the parameters the joints do not feel (base, tool), 1 for the joints' zero
  /// offsets, 2 for their origin errors (urdf_arm_parameter_priority).
  std::vector<int> identification_priority() const override;
  /// The compliance parameters.
  std::vector<int> non_geometric_parameters() const override;
  bool nearer_equivalent(const ParamsRef& params, const ParamsRef& nominal,
                         const std::vector<bool>& changeable, const VectorXd& scale, VectorXd& out,
                         std::string* what) const override;

  /// The geometry with the parameter values `params` (errors, offsets, base, tool).
  UrdfArmGeometry geometry_from(const ParamsRef& params) const;

  /// The pose of the tip link (before the tool frame) at q.
  Pose tip_pose(const ParamsRef& params, const ActuatorsRef& q) const;

  static int base_index() { return 0; }
  static int joint_index(int joint) { return kFrameParameters + kJointParameters * joint; }
  static constexpr int kOffset = 6;  ///< within a joint's block, after the origin error
  int tool_index() const { return joint_index(num_joints()); }
  /// The first compliance parameter (after the tool frame's six).
  int compliance_index() const { return tool_index() + kFrameParameters; }

 private:
  bool is_revolute_joint(int joint) const {
    return geometry_.joints[joint].type != UrdfJointType::kPrismatic;
  }
  /// The links (origin, origin error, joint motion), for serial_chain::walk
  /// (models/urdf_arm.cpp).
  struct Links;
  /// Where the compliance sits, for models/compliant_chain.hpp.
  serial_chain::ComplianceLayout compliance_layout() const;

  UrdfArmGeometry geometry_;
  std::vector<Actuator> actuators_;
  std::vector<Parameter> parameters_;
  JointCompliance compliance_;
  VectorXd gravity_params_;    ///< the gravity geometry: every parameter 0 (the URDF's chain)
  std::vector<Pose> origins_;  ///< C_i
  Pose tip_;                   ///< C_tip
  Pose home_pose_;
  VectorXd home_q_;
};

/// The parameter vector of a geometry, in UrdfArm's layout.
VectorXd urdf_arm_parameters(const UrdfArmGeometry& geometry);

/// The rigid motion of a joint by `value` (rad about the axis, or mm along it).
Pose urdf_joint_motion(const UrdfArmJoint& joint, double value);

/// For each parameter of a model with an urdf-arm mechanism, which to keep when the data
/// cannot tell parameters apart (lower first; identifiable_subset with priorities): -1 the
/// parameters of sensors that are only a point in the measurement frame (a socket's centre:
/// Sensor::frame_vector_reading_index), 0 the frames whose correction the URDF's link frames
/// do not feel (base, tool, the other sensors' own parameters: tracker frame, target, marker),
/// 1 the joints' zero offsets, 2 their origin errors. So a reflector's offset stays in the
/// tool and tcp rather than moving the last link's frame along its axis, and where nothing
/// measured fixes the measurement frame (sockets alone) the base frame holds it: the sockets
/// are estimated in the arm's base coordinates.
std::vector<int> urdf_arm_parameter_priority(const MeasurementModel& model);

/// Frees the parameters of `model` (an urdf-arm mechanism) that its identification Jacobian at
/// nominal determines on 30 fixed configurations around home, joint i of configuration c at
/// home_i + r_i sin(a c + b i + d c i) (r_i the joint's default range), kept by a pivoted QR with
/// urdf_arm_parameter_priority: how the URDF presets choose their free set (each with its own
/// coefficients, so that their configurations differ).
void free_what_home_configurations_determine(MeasurementModel& model, double a, double b, double d);

/// The preset `ur5-urdf` (models/urdf_arm_presets.cpp): its URDF text, description, model.
std::string ur5_urdf_text();
std::string ur5_urdf_description();
std::shared_ptr<MeasurementModel> make_ur5_urdf();
/// The preset `ur5-urdf-compliance`: the same arm with joint compliance and a payload column.
std::string ur5_urdf_compliance_description();
std::shared_ptr<MeasurementModel> make_ur5_urdf_compliance();

/// Registers the urdf-arm type (model-file reader/writer) and the preset ur5-urdf.
void register_urdf_arm(ModelRegistry& registry);

}  // namespace kincal
