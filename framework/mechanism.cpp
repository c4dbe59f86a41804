#include "framework/mechanism.hpp"

#include <Eigen/LU>
#include <cmath>
#include <cstdio>

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
  for (int it = 0;; ++it) {
    constraints(params, q, result.pose, g, &J_g_pose);
    result.iterations = it;
    result.residual_norm = g.cwiseAbs().maxCoeff();
    if (!std::isfinite(result.residual_norm) || !J_g_pose.allFinite()) {
      result.status = ForwardKinematicsStatus::kNonFinite;
      return result;
    }
    if (result.residual_norm <= options.tolerance) {
      result.status = ForwardKinematicsStatus::kConverged;
      return result;
    }
    if (it >= options.max_iterations) {
      result.status = ForwardKinematicsStatus::kMaxIterations;
      return result;
    }
    const Eigen::PartialPivLU<Matrix6d> lu(J_g_pose);
    // rcond from the LU's pivots is cheap; a tiny value means a singular configuration.
    if (!(std::abs(lu.determinant()) > 1e-300) || lu.rcond() < 1e-12) {
      result.status = ForwardKinematicsStatus::kSingular;
      return result;
    }
    const Vector6d step = -options.step_gain * lu.solve(g);
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
  const Eigen::PartialPivLU<Matrix6d> lu(J_g_pose);
  // Column by column with a fixed-size temporary: no heap allocation.
  for (Eigen::Index c = 0; c < J_pose_params.cols(); ++c) {
    const Vector6d column = J_pose_params.col(c);
    J_pose_params.col(c).noalias() = -lu.solve(column);
  }
}

}  // namespace kincal
