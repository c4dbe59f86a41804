#pragma once
// The Mechanism interface: actuators, parameters, kinematics and the pose Jacobian.
//
// A mechanism owns no parameter values: every call takes the mechanism's own slice of the
// parameter vector (layout = parameters()), so one model object serves every iterate of a
// calibration and every thread (Pinocchio's model/data split).

#include <string>
#include <vector>

#include "kincal/framework/parameters.hpp"
#include "kincal/framework/pose.hpp"

namespace kincal {

using ParamsRef = Eigen::Ref<const VectorXd>;
/// Any strided vector binds without a copy, so a row of a (column-major) matrix of
/// configurations can be passed as it is: a contiguous Ref would heap-copy it on every call.
using ActuatorsRef = Eigen::Ref<const VectorXd, 0, Eigen::InnerStride<>>;

struct ForwardKinematicsOptions {
  int max_iterations = 50;
  /// Converged when every constraint residual is below this (mm).
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
  /// One readable sentence, e.g. "did not converge (residual 3.2e-02 mm after 50 iterations)".
  std::string describe() const;
};

class Mechanism {
 public:
  virtual ~Mechanism() = default;

  /// Mechanism type as written in model files, e.g. "hexapod-6ups".
  virtual std::string type() const = 0;
  virtual const std::vector<std::string>& actuator_names() const = 0;
  int num_actuators() const { return static_cast<int>(actuator_names().size()); }
  /// Parameter layout with nominal values and the default free mask.
  virtual const std::vector<Parameter>& parameters() const = 0;
  int num_parameters() const { return static_cast<int>(parameters().size()); }
  /// Pose from which forward kinematics starts by default.
  virtual const Pose& home_pose() const = 0;

  /// Actuator values that put the mechanism at `pose`; q has num_actuators() entries.
  virtual void inverse_kinematics(const ParamsRef& params, const Pose& pose,
                                  Eigen::Ref<VectorXd> q) const = 0;

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

  /// J_out_params = J_out_pose * J_pose_params (k x num_parameters()) for an output of k
  /// values that depends on the pose alone, with J_out_pose (k x 6): how a sensor reading
  /// moves when the parameters move at fixed q. The default forms J_pose_params (and
  /// allocates); closed chains override it with the cheaper adjoint form.
  virtual void output_jacobian_params(const ParamsRef& params, const ActuatorsRef& q,
                                      const Pose& pose,
                                      const Eigen::Ref<const MatrixX6d>& J_out_pose,
                                      Eigen::Ref<MatrixXd> J_out_params) const;
};

/// A mechanism whose pose is defined implicitly by six constraints g(params, q, pose) = 0
/// (parallel manipulators). Forward kinematics is Newton on SE(3) and the pose Jacobian
/// follows from the implicit function theorem: J_pose_params = -J_g_pose^-1 J_g_params.
class ClosedChainMechanism : public Mechanism {
 public:
  /// Constraint residuals g (6) and, when asked for, J_g_pose (6 x 6).
  virtual void constraints(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
                           Vector6d& g, Matrix6d* J_g_pose) const = 0;
  /// J_g_params (6 x num_parameters()).
  virtual void constraint_jacobian_params(const ParamsRef& params, const ActuatorsRef& q,
                                          const Pose& pose,
                                          Eigen::Ref<Matrix6Xd> J_g_params) const = 0;
  /// lambda^T J_g_params (1 x num_parameters()) for a weight vector lambda over the six
  /// constraints, written into `out`. The default forms J_g_params in a per-thread scratch;
  /// a mechanism whose constraint i involves only a few parameters (a hexapod's leg i)
  /// should override it: this is the inner product of output_jacobian_params.
  virtual void constraint_jacobian_params_left(
      const ParamsRef& params, const ActuatorsRef& q, const Pose& pose, const Vector6d& lambda,
      Eigen::Ref<Eigen::RowVectorXd, 0, Eigen::InnerStride<>> out) const;
  /// Cheap validity test of q before iterating (e.g. leg lengths > 0). Default: finite.
  virtual bool actuators_valid(const ParamsRef& params, const ActuatorsRef& q) const;

  ForwardKinematicsResult forward_kinematics(
      const ParamsRef& params, const ActuatorsRef& q, const Pose& start,
      const ForwardKinematicsOptions& options = {}) const override;

  void pose_jacobian_params(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
                            Eigen::Ref<Matrix6Xd> J_pose_params) const override;

  /// Adjoint form: J_out_params = -(J_out_pose J_g_pose^-1) J_g_params, one transposed
  /// 6 x 6 solve per output row instead of the 6 x num_parameters() J_pose_params.
  void output_jacobian_params(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
                              const Eigen::Ref<const MatrixX6d>& J_out_pose,
                              Eigen::Ref<MatrixXd> J_out_params) const override;
};

}  // namespace kincal
