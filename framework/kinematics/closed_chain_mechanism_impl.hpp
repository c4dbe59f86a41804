#pragma once
// Definitions of ClosedChainMechanism<Dof>. Included by closed_chain_mechanism.cpp, which
// compiles Dof = 3 and 6 into the library, and by a mechanism of any other size.

#include <cmath>
#include <optional>

#include "kincal/framework/base/small_lu.hpp"
#include "kincal/framework/kinematics/closed_chain_mechanism.hpp"

namespace kincal {

template <int Dof>
bool ClosedChainMechanism<Dof>::actuators_valid(const ParamsRef&, const ActuatorsRef& q) const {
  return q.allFinite();
}

template <int Dof>
ForwardKinematicsResult ClosedChainMechanism<Dof>::forward_kinematics(
    const ParamsRef& params, const ActuatorsRef& q, const Pose& start,
    const ForwardKinematicsOptions& options) const {
  ForwardKinematicsResult result;
  result.pose = start;
  if (!actuators_valid(params, q)) {
    result.status = ForwardKinematicsStatus::kInvalidActuators;
    return result;
  }
  ConstraintVector g;
  ConstraintJacobian J_g_pose;
  std::optional<SmallLu<Dof>> lu;  // of J_g_pose at the previous iterate
  for (int it = 0;; ++it) {
    constraints(params, q, result.pose, g, &J_g_pose);
    result.iterations = it;
    result.residual_norm = g.cwiseAbs().maxCoeff();
    // A non-finite J_g_pose with finite residuals (a leg of zero length) shows up as
    // non-finite pivots, which near_singular() reports.
    if (!std::isfinite(result.residual_norm)) {
      result.status = ForwardKinematicsStatus::kNonFinite;
      return result;
    }
    if (result.residual_norm <= options.tolerance) {
      // One last full Newton step, not checked: it takes the residual from the tolerance to
      // the rounding level (quadratic convergence). Without it the pose, hence every
      // predicted reading, jumps by up to the tolerance whenever the number of Newton steps
      // changes between two nearby parameter vectors: noise of ~1e-8 relative in the cost,
      // which stalled the solvers' end game far above their tolerances. The previous
      // iterate's factorisation serves: it is at most a step away, so the chord step
      // still lands at rounding level, and a factorisation is a tenth of the time here.
      // Converged at the start pose, there is none yet: a fresh one must be checked like
      // every other, or a start exactly at a singular solution would divide by a zero pivot
      // and return a NaN pose as converged.
      if (!lu) {
        lu.emplace(J_g_pose);
        if (lu->near_singular(J_g_pose)) {
          result.status = ForwardKinematicsStatus::kSingular;
          return result;
        }
      }
      result.pose = moved(result.pose, -lu->solve(g));
      result.status = ForwardKinematicsStatus::kConverged;
      return result;
    }
    if (it >= options.max_iterations) {
      result.status = ForwardKinematicsStatus::kMaxIterations;
      return result;
    }
    lu.emplace(J_g_pose);
    if (lu->near_singular(J_g_pose)) {
      result.status = ForwardKinematicsStatus::kSingular;
      return result;
    }
    const ConstraintVector step = -options.step_gain * lu->solve(g);
    result.pose = moved(result.pose, step);
  }
}

template <int Dof>
void ClosedChainMechanism<Dof>::pose_jacobian_params(const ParamsRef& params, const ActuatorsRef& q,
                                                     const Pose& pose,
                                                     Eigen::Ref<Matrix6Xd> J_pose_params) const {
  ConstraintVector g;
  ConstraintJacobian J_g_pose;
  constraints(params, q, pose, g, &J_g_pose);
  // One inverse and fixed-size products beat a solve per parameter column (42 of them for a
  // hexapod). Column by column with fixed-size temporaries: no heap allocation.
  const ConstraintJacobian minus_inverse = -SmallLu<Dof>(J_g_pose).inverse();
  if constexpr (Dof == 6) {
    constraint_jacobian_params(params, q, pose, J_pose_params);
    for (Eigen::Index c = 0; c < J_pose_params.cols(); ++c) {
      const Vector6d column = J_pose_params.col(c);
      J_pose_params.col(c).noalias() = minus_inverse * column;
    }
  } else {
    thread_local ParamsJacobian J_g_params;
    J_g_params.resize(Dof, num_parameters());  // no reallocation once the size is right
    constraint_jacobian_params(params, q, pose, J_g_params);
    const MotionBasis map = basis_ * minus_inverse;
    for (Eigen::Index c = 0; c < J_pose_params.cols(); ++c)
      J_pose_params.col(c).noalias() = map * J_g_params.col(c);
  }
}

template <int Dof>
bool ClosedChainMechanism<Dof>::pose_jacobian_actuators(
    const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
    const ForwardKinematicsOptions&, Eigen::Ref<Matrix6Xd> J_pose_actuators) const {
  ConstraintVector g_plus, g_minus;
  ConstraintJacobian J_g_pose;
  constraints(params, q, pose, g_plus, &J_g_pose);
  const SmallLu<Dof> lu(J_g_pose);
  if (!g_plus.allFinite() || lu.near_singular(J_g_pose)) return false;
  VectorXd moved = q;
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    const double h = 1e-6 * (1 + std::abs(q[i]));
    moved[i] = q[i] + h;
    constraints(params, moved, pose, g_plus, nullptr);
    moved[i] = q[i] - h;
    constraints(params, moved, pose, g_minus, nullptr);
    moved[i] = q[i];
    const ConstraintVector dg_dq = (g_plus - g_minus) / (2 * h);
    // The pose moves so that the constraints stay 0: J_g_pose d_local + J_g_q dq = 0.
    if constexpr (Dof == 6)
      J_pose_actuators.col(i) = -lu.solve(dg_dq);
    else
      J_pose_actuators.col(i) = basis_ * -lu.solve(dg_dq);
  }
  return J_pose_actuators.allFinite();
}

template <int Dof>
void ClosedChainMechanism<Dof>::constraint_jacobian_params_left(
    const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
    const ConstraintVector& lambda,
    Eigen::Ref<Eigen::RowVectorXd, 0, Eigen::InnerStride<>> out) const {
  thread_local ParamsJacobian J_g_params;
  J_g_params.resize(Dof, num_parameters());  // no reallocation once the size is right
  constraint_jacobian_params(params, q, pose, J_g_params);
  out.noalias() = lambda.transpose() * J_g_params;
}

template <int Dof>
void ClosedChainMechanism<Dof>::output_jacobian_params(
    const ParamsRef& params, const ActuatorsRef& q, const Pose& pose,
    const Eigen::Ref<const MatrixX6d>& J_out_pose, Eigen::Ref<MatrixXd> J_out_params) const {
  ConstraintVector g;
  ConstraintJacobian J_g_pose;
  constraints(params, q, pose, g, &J_g_pose);
  // Row r: J_out_pose.row(r) E J_pose_local = -lambda^T J_g_params with
  // J_g_pose^T lambda = (J_out_pose.row(r) E)^T.
  const SmallLu<Dof> lu(J_g_pose);
  for (Eigen::Index r = 0; r < J_out_pose.rows(); ++r) {
    ConstraintVector local;
    if constexpr (Dof == 6)
      local = J_out_pose.row(r).transpose();
    else
      local.noalias() = basis_.transpose() * J_out_pose.row(r).transpose();
    const ConstraintVector lambda = -lu.solve_transposed(local);
    constraint_jacobian_params_left(params, q, pose, lambda, J_out_params.row(r));
  }
}

}  // namespace kincal
