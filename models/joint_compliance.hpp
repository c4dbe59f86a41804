#pragma once
// Joint compliance under gravity, for serial chains (docs/theory.md, "Joint compliance under
// gravity"). Each moving joint i deflects by
//
//   delta_i = c_i tau_i(q, payload)
//
// added to its joint value before the geometric chain, where tau_i is the static torque
// (revolute, N m) or force (prismatic, N) gravity exerts on joint i: the moment about joint
// i's axis of the weight of every mass beyond it (one step of a recursive Newton-Euler pass
// at rest: no velocity, no acceleration, so only the gravity terms remain), and c_i its
// compliance (rad/Nm, or mm/N for a prismatic joint).
//
// The masses come from one of two places:
//   given    a mass and centre of mass per link (a URDF's <inertial> elements, or the model
//            file): the compliances c_i are the parameters.
//   fitted   no masses known: every link's weight is a point mass at the origin of the next
//            joint's frame (and at the tip link's origin) whose product with the compliance
//            of each joint before it is a parameter, the joint's "moment" of that point
//            (rad per m of lever, or mm for a prismatic joint):
//              delta_i = sum_k mu_ik g_hat . (a_i x (p_k - o_i))
//            Mass and compliance are not separable from deflections alone, their products
//            are; linear in the parameters, so the identifiable-set choice (a pivoted QR on
//            the identification Jacobian) sees which products the data determine.
// A payload (mass per row from a measurement column, or per model; centre in the tip link's
// frame) adds its moment to every joint, through c_i in both cases: data taken with
// different payloads separate the compliances from the links' own weight.
//
// Gravity's direction is given in the chain's base link frame (default -z: a robot on the
// floor) and tilted by two parameters gravity.rx, gravity.ry (rad, fixed unless freed): a
// robot on a wall or a ceiling sets the direction, a slightly tilted base frees the tilt.
//
// The torques are computed on the chain's nominal geometry (its constant link origins and
// axes, at the commanded joint values, without the calibrated corrections and without the
// deflection itself): the corrections change a torque by their relative size (1e-3), so the
// deflection by 1e-3 of itself, far below any measurement (docs/theory.md). In exchange the
// deflection does not depend on the geometric parameters, and the analytic Jacobian is exact.
//
// Limits: gravity only (no dynamics, no backlash, no link bending), linear joint stiffness.

#include <Eigen/Core>
#include <set>
#include <string>
#include <vector>

#include "kincal/framework/kinematics/mechanism.hpp"

#include "kincal/framework/kinematics/parameters.hpp"
#include "kincal/framework/kinematics/pose.hpp"

namespace kincal {

/// Standard gravity (m/s^2): a torque in N m is kg * mm * this / 1000.
inline constexpr double kStandardGravity = 9.80665;
/// The most moving joints a compliant chain may have (fixed-size scratch in the kernels).
inline constexpr int kMaxCompliantJoints = 12;

/// Base units of the compliance parameters (framework/kinematics/units.hpp).
inline constexpr const char* kRadianPerNewtonMetre = "rad/Nm";
inline constexpr const char* kMillimetrePerNewton = "mm/N";
inline constexpr const char* kRadianPerMetre = "rad/m";
inline constexpr const char* kKilogram = "kg";

/// A rigid body's mass (kg) and centre of mass (mm, in a link's frame).
struct PointMass {
  double mass = 0;
  Vector3d centre = Vector3d::Zero();
};

enum class GravityMasses { kGiven, kFitted };
const char* to_string(GravityMasses masses);

/// A chain's compliance model as a model file states it (models/urdf_arm_type.cpp).
struct ComplianceSpec {
  bool enabled = false;
  GravityMasses masses = GravityMasses::kGiven;
  /// kGiven: per moving joint, what its child link carries rigidly (the link and every link
  /// fixed to it before the next moving joint), centre in the child link's frame.
  std::vector<PointMass> links;
  /// Where the masses came from, for reports: "URDF inertials", "model file".
  std::string masses_source;
  /// Unit direction of gravity in the base link's frame, before the tilt parameters.
  Vector3d gravity = -Vector3d::UnitZ();
  /// The payload when no column gives it: mass (kg) and centre in the tip link's frame (mm).
  PointMass payload;
  /// The payload's mass is a measurement column, actuator "payload" (kg), drawn in [0, max]
  /// by simulation and design.
  bool payload_column = false;
  double payload_max = 5.0;
  /// Parameter values by name (the compliance parameters only; zero when absent).
  std::vector<std::pair<std::string, double>> values;
};

/// The chain at one configuration as gravity sees it: per moving joint its unit axis and a
/// point on it (revolute) and the origin of its child link's frame, and the tip link's frame,
/// all in the base link's frame (mm). Filled by the mechanism on its nominal geometry.
struct GravityChain {
  int joints = 0;
  bool revolute[kMaxCompliantJoints] = {};
  Vector3d axis[kMaxCompliantJoints];
  Vector3d origin[kMaxCompliantJoints];
  Pose link[kMaxCompliantJoints];  ///< joint i's child link, after its motion
  Pose tip;
};

/// Deflections per joint and their derivatives with respect to the compliance parameters.
using JointVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxCompliantJoints, 1>;
inline constexpr int kMaxComplianceParameters =
    2 + kMaxCompliantJoints + kMaxCompliantJoints * (kMaxCompliantJoints + 1) / 2;
using DeflectionJacobian = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0,
                                         kMaxCompliantJoints, kMaxComplianceParameters>;

/// The compliance parameters of one chain and the deflections they give.
class JointCompliance {
 public:
  JointCompliance() = default;
  /// For a chain of `joint_names` (revolute or not per `revolute`). Throws
  /// std::invalid_argument for a spec it cannot use (too many joints, masses per link that do
  /// not match the joints, a negative or non-finite mass, a zero gravity direction, a value
  /// naming no compliance parameter).
  JointCompliance(const ComplianceSpec& spec, const std::vector<std::string>& joint_names,
                  const std::vector<bool>& revolute);

  bool enabled() const { return spec_.enabled; }
  const ComplianceSpec& spec() const { return spec_; }
  /// The parameters, in order: gravity.rx, gravity.ry, then `<joint>.compliance` per joint
  /// (kGiven, or kFitted with a payload), then kFitted's `<joint_i>.moment.<joint_k>` and
  /// `<joint_i>.moment.tip`. Values from the spec, all fixed.
  const std::vector<Parameter>& parameters() const { return parameters_; }
  int num_parameters() const { return static_cast<int>(parameters_.size()); }
  /// Sets the parameters' tolerances (the half-width of the errors a simulation draws, and
  /// what the calibration verdict compares corrections with) so that each compliance or
  /// moment at its tolerance deflects its joint by at most 1 mrad (1 mm prismatic) with the
  /// masses at their distances from the joint in `chain` (the arm at home): a light wrist's
  /// compliance may be 100 times a heavy shoulder's.
  void scale_tolerances(const GravityChain& chain);
  /// Adds what an arm takes from this compliance: its parameters after `parameters` and, when
  /// the payload's mass is a column, the actuator "payload" (kg, not commanded, drawn in
  /// [0, max] by simulation and design) after `actuators`. `names` holds the names already
  /// taken; `arm` names the arm in messages. Throws std::invalid_argument on a name taken twice.
  void add_to(std::vector<Parameter>& parameters, std::vector<Actuator>& actuators,
              std::set<std::string>& names, const std::string& arm) const;
  /// `geometric` (an arm's other parameters) followed by this block's values.
  VectorXd appended_to(const VectorXd& geometric) const;
  /// The indices of its parameters when the first is at `first`.
  std::vector<int> indices(int first) const;
  /// The spec with the parameter values `values` (this block's slice).
  ComplianceSpec spec_with(const Eigen::Ref<const VectorXd>& values) const;

  /// delta (joints) at the chain `chain` with the parameter block `values` and payload mass
  /// `payload` (kg); dDelta (joints x num_parameters()) when given. Nothing allocated.
  void deflections(const GravityChain& chain, const double* values, double payload,
                   JointVector& delta, DeflectionJacobian* dDelta) const;

 private:
  ComplianceSpec spec_;
  std::vector<std::string> joint_names_;
  std::vector<bool> revolute_;
  std::vector<Parameter> parameters_;
  bool has_compliances_ = false;
  int compliance_index_ = 2;  ///< first <joint>.compliance
  int moment_index_ = 2;      ///< first moment
  /// kFitted: (joint i, point k) of each moment parameter; k == joints: the tip.
  std::vector<std::pair<int, int>> moments_;
};

/// Gravity's unit direction tilted by rx about x, then ry about y (R = Ry Rx), and its
/// derivatives.
Vector3d tilted_gravity(const Vector3d& g0, double rx, double ry, Vector3d* d_rx = nullptr,
                        Vector3d* d_ry = nullptr);

}  // namespace kincal
