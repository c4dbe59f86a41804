#pragma once
// A mechanism whose pose is defined implicitly by Dof constraints g(params, q, pose) = 0
// (parallel manipulators): a hexapod has six, a planar 3-RPR robot three. The pose moves in
// a Dof-dimensional subspace of SE(3) spanned by the columns of motion_basis() (identity for
// a spatial mechanism; dx, dy and a rotation about z for a planar one), and every Jacobian
// with respect to the pose is taken in those local coordinates.
//
// Forward kinematics is Newton on that subspace, and the pose Jacobian follows from the
// implicit function theorem: J_pose_params = -E J_g_pose^-1 J_g_params, E the motion basis.
// Dof is a compile-time size so that every per-configuration kernel works on fixed-size
// Eigen types (the 6 x 6 case uses the unrolled Lu6). Sizes 3 and 6 are compiled into the
// library; a mechanism of another size includes closed_chain_mechanism_impl.hpp.

#include <type_traits>

#include "kincal/framework/kinematics/mechanism.hpp"

namespace kincal {

template <int Dof>
class ClosedChainMechanism : public Mechanism {
  static_assert(Dof >= 1 && Dof <= 6, "a rigid pose has at most six degrees of freedom");

 public:
  static constexpr int kDof = Dof;
  using ConstraintVector = Eigen::Matrix<double, Dof, 1>;
  using ConstraintJacobian = Eigen::Matrix<double, Dof, Dof>;
  using ParamsJacobian = Eigen::Matrix<double, Dof, Eigen::Dynamic>;
  using MotionBasis = Eigen::Matrix<double, 6, Dof>;

  /// Newton from home_pose finds the assembly nearest it (data_checks.hpp warns when the data
  /// lie far from home_pose).
  bool forward_kinematics_has_assemblies() const override { return true; }

  /// Constraint residuals g and, when asked for, J_g_pose (Dof x Dof, local coordinates).
  virtual void constraints(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
                           ConstraintVector& g, ConstraintJacobian* J_g_pose) const = 0;
  /// J_g_params (Dof x num_parameters()).
  virtual void constraint_jacobian_params(const ParamsRef& params, const ActuatorsRef& q,
                                          const Pose& pose,
                                          Eigen::Ref<ParamsJacobian> J_g_params) const = 0;
  /// lambda^T J_g_params (1 x num_parameters()) for a weight vector lambda over the
  /// constraints, written into `out`. The default forms J_g_params in a per-thread scratch;
  /// a mechanism whose constraint i involves only a few parameters (a hexapod's leg i)
  /// should override it: this is the inner product of output_jacobian_params.
  virtual void constraint_jacobian_params_left(
      const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
      const ConstraintVector& lambda,
      Eigen::Ref<Eigen::RowVectorXd, 0, Eigen::InnerStride<>> out) const;
  /// Cheap validity test of q before iterating (e.g. leg lengths > 0). Default: finite.
  virtual bool actuators_valid(const ParamsRef& params, const ActuatorsRef& q) const;

  /// Column k: the SE(3) perturbation [dt; dw] of local pose coordinate k.
  const MotionBasis& motion_basis() const { return basis_; }

  ForwardKinematicsResult forward_kinematics(
      const ParamsRef& params, const ActuatorsRef& q, const Pose& start,
      const ForwardKinematicsOptions& options = {}) const override;

  void pose_jacobian_params(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
                            Eigen::Ref<Matrix6Xd> J_pose_params) const override;

  /// -E J_g_pose^-1 J_g_q, with J_g_q from central differences of the constraints (cheap:
  /// no Newton iteration, and the constraints are smooth in q).
  bool pose_jacobian_actuators(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
                               const ForwardKinematicsOptions& options,
                               Eigen::Ref<Matrix6Xd> J_pose_actuators) const override;
  /// Adjoint form: J_out_params = -(J_out_pose E J_g_pose^-1) J_g_params, one transposed
  /// Dof x Dof solve per output row instead of the 6 x num_parameters() J_pose_params.
  void output_jacobian_params(const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
                              const Eigen::Ref<const MatrixX6d>& J_out_pose,
                              Eigen::Ref<MatrixXd> J_out_params) const override;

 protected:
  /// Spatial mechanisms (Dof = 6) need no basis: it is the identity.
  ClosedChainMechanism() : basis_(MotionBasis::Identity()) {}
  /// Only for Dof < 6: the Dof = 6 kernels take the basis as the identity without reading it.
  template <int D = Dof, typename = std::enable_if_t<(D < 6)>>
  explicit ClosedChainMechanism(const MotionBasis& basis) : basis_(basis) {}

  /// The pose moved by local coordinates `step`.
  Pose moved(const Pose& pose, const ConstraintVector& step) const {
    if constexpr (Dof == 6) return perturb(pose, step);
    return perturb(pose, basis_ * step);
  }

 private:
  MotionBasis basis_;
};

extern template class ClosedChainMechanism<3>;
extern template class ClosedChainMechanism<6>;

}  // namespace kincal
