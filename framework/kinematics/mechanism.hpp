#pragma once
// The Mechanism interface: actuators, parameters, kinematics and the pose Jacobian.
//
// A mechanism owns no parameter values: every call takes the mechanism's own slice of the
// parameter vector (layout = parameters()), so one model object serves every iterate of a
// calibration and every thread (Pinocchio's model/data split).

#include <limits>
#include <string>
#include <vector>

#include "kincal/framework/kinematics/parameters.hpp"
#include "kincal/framework/kinematics/pose.hpp"

namespace kincal {

using ParamsRef = Eigen::Ref<const VectorXd>;
/// Any strided vector binds without a copy, so a row of a (column-major) matrix of
/// configurations can be passed as it is: a contiguous Ref would heap-copy it on every call.
using ActuatorsRef = Eigen::Ref<const VectorXd, 0, Eigen::InnerStride<>>;

/// One actuated joint: what a measurement file's column holds and in which unit.
struct Actuator {
  std::string name;  ///< column name in measurement files, e.g. "leg1", "joint2"
  std::string unit;  ///< "mm" (prismatic) or "rad" (revolute)
  /// Half-width, in `unit`, of the box around the home configuration from which simulation
  /// and experiment design draw configurations unless told otherwise (model file or CLI).
  double default_range = 0;
  /// Whether a controller commands it (a joint, a leg); false for an input the mechanism
  /// reads but nobody commands (a payload's mass): compensation leaves it as given.
  bool commanded = true;
  /// The joint's limits in `unit` (a URDF's <limit>); infinite where it has none. Experiment
  /// design draws only within them, and by default within them where every joint has some.
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
};

struct ForwardKinematicsOptions {
  int max_iterations = 50;
  /// Converged when every constraint residual is below this (in the constraints' units).
  double tolerance = 1e-10;
  /// The paper's gain k on the Newton step (eq. 11); 1 = plain Newton.
  double step_gain = 1.0;
};

enum class ForwardKinematicsStatus {
  kConverged,
  kMaxIterations,     ///< Newton did not reach the tolerance
  kSingular,          ///< constraint Jacobian singular (singular configuration)
  kInvalidActuators,  ///< e.g. a negative leg length
  kNonFinite,         ///< NaN/Inf appeared
};

const char* to_string(ForwardKinematicsStatus status);

struct ForwardKinematicsResult {
  Pose pose;
  ForwardKinematicsStatus status = ForwardKinematicsStatus::kConverged;
  int iterations = 0;
  double residual_norm = 0;  ///< max-norm of the constraints at `pose`
  bool ok() const { return status == ForwardKinematicsStatus::kConverged; }
  /// One readable sentence, e.g. "did not converge (residual 3.2e-02 after 50 iterations)".
  std::string describe() const;
};

enum class InverseKinematicsStatus {
  kSolved,
  kUnreachable,   ///< no actuator values reach the pose (e.g. a leg would be negative)
  kNotConverged,  ///< an iterative solver stopped before reaching the pose
  kNonFinite,     ///< the pose or the parameters hold NaN/Inf
};

const char* to_string(InverseKinematicsStatus status);

struct InverseKinematicsResult {
  InverseKinematicsStatus status = InverseKinematicsStatus::kSolved;
  int iterations = 0;        ///< 0 for closed-form inverse kinematics
  double residual_norm = 0;  ///< pose error left by an iterative solver (mm and rad mixed)
  std::string reason;        ///< what made it fail, in the mechanism's words
  bool ok() const { return status == InverseKinematicsStatus::kSolved; }
  /// One readable sentence, e.g. "unreachable: leg 3 would be -4.2 mm long".
  std::string describe() const;
};

class Mechanism {
 public:
  virtual ~Mechanism() = default;

  /// Mechanism type as written in model files, e.g. "hexapod-6ups".
  virtual std::string type() const = 0;
  /// The actuated joints, in the order of actuator vectors q.
  virtual const std::vector<Actuator>& actuators() const = 0;
  int num_actuators() const { return static_cast<int>(actuators().size()); }
  std::vector<std::string> actuator_names() const;
  /// Parameter layout with nominal values and units; all fixed (a model's mask frees them).
  virtual const std::vector<Parameter>& parameters() const = 0;
  int num_parameters() const { return static_cast<int>(parameters().size()); }
  /// Pose from which forward kinematics starts by default.
  virtual const Pose& home_pose() const = 0;
  /// Whether forward kinematics has several solutions (assemblies) and converges to the one
  /// nearest its start, so that a wrong home_pose gives other valid poses: true for closed
  /// chains (ClosedChainMechanism says so), false where forward kinematics is closed form and
  /// unique (serial arms, imported or not), the default.
  virtual bool forward_kinematics_has_assemblies() const { return false; }
  /// Actuator values at home, around which configurations are drawn. Default: inverse
  /// kinematics of home_pose(); a serial arm returns its home joint values.
  virtual InverseKinematicsResult home_actuators(const ParamsRef& params,
                                                 Eigen::Ref<VectorXd> q) const;

  /// Actuator values that put the mechanism at `pose`; q has num_actuators() entries. A pose
  /// no actuator values reach is a status with a reason, never a NaN in q.
  virtual InverseKinematicsResult inverse_kinematics(const ParamsRef& params, const Pose& pose,
                                                     Eigen::Ref<VectorXd> q) const = 0;

  /// The same, starting from the actuator values `start`: where inverse kinematics is
  /// iterative and has several solutions (a serial arm's branches), the one it reaches from
  /// `start`, the nearest in practice. The default ignores `start` (closed-form inverse
  /// kinematics, one solution: a parallel mechanism's legs).
  virtual InverseKinematicsResult inverse_kinematics_near(const ParamsRef& params, const Pose& pose,
                                                          const ActuatorsRef& start,
                                                          Eigen::Ref<VectorXd> q) const {
    (void)start;
    return inverse_kinematics(params, pose, q);
  }
  /// Pose reached with actuator values q, iterating from `start`. Never returns a pose that
  /// does not satisfy the kinematics: failure is a status with a reason.
  virtual ForwardKinematicsResult forward_kinematics(
      const ParamsRef& params, const ActuatorsRef& q, const Pose& start,
      const ForwardKinematicsOptions& options = {}) const = 0;

  /// J_pose_params (6 x num_parameters()): how the pose reached at fixed q moves when the
  /// parameters move, in the perturbation convention of pose.hpp.
  virtual void pose_jacobian_params(const ParamsRef& params, const ActuatorsRef& q,
                                    const Pose& pose,
                                    Eigen::Ref<Matrix6Xd> J_pose_params) const = 0;

  /// J_pose_actuators (6 x num_actuators()): how the pose reached at q moves when the
  /// actuators move (local perturbation of `pose`, the pose reached at q), per unit of each
  /// actuator. False when it cannot be computed (forward kinematics fails next to q, or q is
  /// singular). The default takes central differences of forward kinematics; closed chains
  /// override it with the implicit-function form, which needs no forward kinematics.
  virtual bool pose_jacobian_actuators(const ParamsRef& params, const ActuatorsRef& q,
                                       const Pose& pose, const ForwardKinematicsOptions& options,
                                       Eigen::Ref<Matrix6Xd> J_pose_actuators) const;

  /// J_out_params = J_out_pose * J_pose_params (k x num_parameters()) for an output of k
  /// values that depends on the pose alone, with J_out_pose (k x 6): how a sensor reading
  /// moves when the parameters move at fixed q. The default forms J_pose_params in a
  /// per-thread scratch; closed chains override it with the cheaper adjoint form.
  virtual void output_jacobian_params(const ParamsRef& params, const ActuatorsRef& q,
                                      const Pose& pose,
                                      const Eigen::Ref<const MatrixX6d>& J_out_pose,
                                      Eigen::Ref<MatrixXd> J_out_params) const;

  /// For a parametrisation with discrete symmetries (a revolute joint's zero turned by pi,
  /// the next link's frame turned with it: the links drawn flipped, every pose the same), the
  /// equivalent parameter vector nearest `nominal` reachable from `params` by them, in `out`,
  /// with what was mapped in words. Only parameters whose `changeable` entry is true may
  /// differ from `params`; the distance to nominal is sum ((value - nominal) / scale)^2,
  /// angles taken on their branch nearest nominal. False when none is nearer than `params`
  /// (the default: no symmetry known). The caller checks that the predictions are unchanged
  /// (framework/calibration/equivalent_solutions.hpp), so a wrong map is never used.
  virtual bool nearer_equivalent(const ParamsRef& params, const ParamsRef& nominal,
                                 const std::vector<bool>& changeable, const VectorXd& scale,
                                 VectorXd& out, std::string* what) const;

  /// Which of this mechanism's parameters to keep first when the data cannot determine them
  /// all (framework/analysis/identifiability.hpp, identifiable_subset: lower is kept first),
  /// one entry per parameter; empty (the default) for no preference. An arm whose error model
  /// is redundant on purpose says here which of two equivalent parameters should carry the
  /// error (models/urdf_arm.hpp).
  virtual std::vector<int> identification_priority() const { return {}; }
  /// The parameters that are not geometry (a joint's compliance under gravity,
  /// models/joint_compliance.hpp): what a kinematic description (URDF, DH table) cannot hold,
  /// so that a report can say what loading only the geometry leaves uncorrected. Empty (the
  /// default): every parameter is geometry.
  virtual std::vector<int> non_geometric_parameters() const { return {}; }
};

}  // namespace kincal
