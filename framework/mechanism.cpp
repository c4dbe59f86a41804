#include "kincal/framework/mechanism.hpp"

#include <cmath>
#include <cstdio>
#include <optional>

#include "kincal/framework/lu6.hpp"

namespace kincal {

const char* to_string(ForwardKinematicsStatus status) {
  switch (status) {
    case ForwardKinematicsStatus::kConverged:
      return "converged";
    case ForwardKinematicsStatus::kMaxIterations:
      return "max_iterations";
    case ForwardKinematicsStatus::kSingular:
      return "singular";
    case ForwardKinematicsStatus::kInvalidActuators:
      return "invalid_actuators";
    case ForwardKinematicsStatus::kNonFinite:
      return "non_finite";
  }
  return "unknown";
}

std::string ForwardKinematicsResult::describe() const {
  char buf[160];
  switch (status) {
    case ForwardKinematicsStatus::kConverged:
      std::snprintf(buf, sizeof buf, "converged in %d iterations", iterations);
      break;
    case ForwardKinematicsStatus::kMaxIterations:
      std::snprintf(buf, sizeof buf, "did not converge (residual %.3g mm after %d iterations)",
                    residual_norm, iterations);
      break;
    case ForwardKinematicsStatus::kSingular:
      std::snprintf(buf, sizeof buf, "hit a singular configuration after %d iterations",
                    iterations);
      break;
    case ForwardKinematicsStatus::kInvalidActuators:
      std::snprintf(buf, sizeof buf, "actuator values are invalid (e.g. negative leg length)");
      break;
    case ForwardKinematicsStatus::kNonFinite:
      std::snprintf(buf, sizeof buf, "produced non-finite values after %d iterations", iterations);
      break;
  }
  return buf;
}

bool ClosedChainMechanism::actuators_valid(const ParamsRef&, const ActuatorsRef& q) const {
  return q.allFinite();
}

ForwardKinematicsResult ClosedChainMechanism::forward_kinematics(
    const ParamsRef& params, const ActuatorsRef& q, const Pose& start,
    const ForwardKinematicsOptions& options) const {
  ForwardKinematicsResult result;
  result.pose = start;
  if (!actuators_valid(params, q)) {
    result.status = ForwardKinematicsStatus::kInvalidActuators;
    return result;
  }
  Vector6d g;
  Matrix6d J_g_pose;
  std::optional<Lu6> lu;  // of J_g_pose at the previous iterate
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
      if (!lu) lu.emplace(J_g_pose);
      result.pose = perturb(result.pose, -lu->solve(g));
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
    const Vector6d step = -options.step_gain * lu->solve(g);
    result.pose = perturb(result.pose, step);
  }
}

void ClosedChainMechanism::pose_jacobian_params(const ParamsRef& params, const ActuatorsRef& q,
                                                const Pose& pose,
                                                Eigen::Ref<Matrix6Xd> J_pose_params) const {
  Vector6d g;
  Matrix6d J_g_pose;
  constraints(params, q, pose, g, &J_g_pose);
  constraint_jacobian_params(params, q, pose, J_pose_params);
  // One inverse and fixed-size products beat a solve per parameter column (42 of them for a
  // hexapod). Column by column with a fixed-size temporary: no heap allocation.
  const Matrix6d minus_inverse = -Lu6(J_g_pose).inverse();
  for (Eigen::Index c = 0; c < J_pose_params.cols(); ++c) {
    const Vector6d column = J_pose_params.col(c);
    J_pose_params.col(c).noalias() = minus_inverse * column;
  }
}

void Mechanism::output_jacobian_params(const ParamsRef& params, const ActuatorsRef& q,
                                       const Pose& pose,
                                       const Eigen::Ref<const MatrixX6d>& J_out_pose,
                                       Eigen::Ref<MatrixXd> J_out_params) const {
  Matrix6Xd J_pose_params(6, num_parameters());
  pose_jacobian_params(params, q, pose, J_pose_params);
  J_out_params.noalias() = J_out_pose * J_pose_params;
}

void ClosedChainMechanism::constraint_jacobian_params_left(
    const ParamsRef& params, const ActuatorsRef& q, const Pose& pose, const Vector6d& lambda,
    Eigen::Ref<Eigen::RowVectorXd, 0, Eigen::InnerStride<>> out) const {
  thread_local Matrix6Xd J_g_params;
  J_g_params.resize(6, num_parameters());  // no reallocation once the size is right
  constraint_jacobian_params(params, q, pose, J_g_params);
  out.noalias() = lambda.transpose() * J_g_params;
}

void ClosedChainMechanism::output_jacobian_params(const ParamsRef& params, const ActuatorsRef& q,
                                                  const Pose& pose,
                                                  const Eigen::Ref<const MatrixX6d>& J_out_pose,
                                                  Eigen::Ref<MatrixXd> J_out_params) const {
  Vector6d g;
  Matrix6d J_g_pose;
  constraints(params, q, pose, g, &J_g_pose);
  // Row r: J_out_pose.row(r) * J_pose_params = -lambda^T J_g_params with
  // J_g_pose^T lambda = J_out_pose.row(r)^T.
  const Lu6 lu(J_g_pose);
  for (Eigen::Index r = 0; r < J_out_pose.rows(); ++r) {
    const Vector6d lambda = -lu.solve_transposed(J_out_pose.row(r).transpose());
    constraint_jacobian_params_left(params, q, pose, lambda, J_out_params.row(r));
  }
}

}  // namespace kincal
