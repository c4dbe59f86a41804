#include "kincal/framework/kinematics/mechanism.hpp"

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
      std::snprintf(buf, sizeof buf, "did not converge (residual %.3g after %d iterations)",
                    residual_norm, iterations);
      break;
    case ForwardKinematicsStatus::kSingular:
      std::snprintf(buf, sizeof buf, "hit a singular configuration after %d iterations",
                    iterations);
      break;
    case ForwardKinematicsStatus::kInvalidActuators:
      std::snprintf(buf, sizeof buf,
                    "actuator values are invalid (outside what the mechanism can take, e.g. a "
                    "leg shorter than zero)");
      break;
    case ForwardKinematicsStatus::kNonFinite:
      std::snprintf(buf, sizeof buf, "produced non-finite values after %d iterations", iterations);
      break;
  }
  return buf;
}

const char* to_string(InverseKinematicsStatus status) {
  switch (status) {
    case InverseKinematicsStatus::kSolved:
      return "solved";
    case InverseKinematicsStatus::kUnreachable:
      return "unreachable";
    case InverseKinematicsStatus::kNotConverged:
      return "not_converged";
    case InverseKinematicsStatus::kNonFinite:
      return "non_finite";
  }
  return "unknown";
}

std::string InverseKinematicsResult::describe() const {
  std::string text;
  switch (status) {
    case InverseKinematicsStatus::kSolved:
      text = "solved";
      break;
    case InverseKinematicsStatus::kUnreachable:
      text = "the pose is unreachable";
      break;
    case InverseKinematicsStatus::kNotConverged: {
      char buf[96];
      std::snprintf(buf, sizeof buf, "did not converge (pose error %.3g after %d iterations)",
                    residual_norm, iterations);
      text = buf;
      break;
    }
    case InverseKinematicsStatus::kNonFinite:
      text = "non-finite values in the pose or the parameters";
      break;
  }
  return reason.empty() ? text : text + ": " + reason;
}

std::vector<std::string> Mechanism::actuator_names() const {
  std::vector<std::string> names;
  for (const auto& a : actuators()) names.push_back(a.name);
  return names;
}

InverseKinematicsResult Mechanism::home_actuators(const ParamsRef& params,
                                                  Eigen::Ref<VectorXd> q) const {
  return inverse_kinematics(params, home_pose(), q);
}

void Mechanism::output_jacobian_params(const ParamsRef& params, const ActuatorsRef& q,
                                       const Pose& pose,
                                       const Eigen::Ref<const MatrixX6d>& J_out_pose,
                                       Eigen::Ref<MatrixXd> J_out_params) const {
  thread_local Matrix6Xd J_pose_params;
  J_pose_params.resize(6, num_parameters());  // no reallocation once the size is right
  pose_jacobian_params(params, q, pose, J_pose_params);
  J_out_params.noalias() = J_out_pose * J_pose_params;
}

bool Mechanism::pose_jacobian_actuators(const ParamsRef& params, const ActuatorsRef& q,
                                        const Pose& pose, const ForwardKinematicsOptions& options,
                                        Eigen::Ref<Matrix6Xd> J_pose_actuators) const {
  VectorXd moved = q;
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    const double h = 1e-6 * (1 + std::abs(q[i]));
    moved[i] = q[i] + h;
    const ForwardKinematicsResult plus = forward_kinematics(params, moved, pose, options);
    moved[i] = q[i] - h;
    const ForwardKinematicsResult minus = forward_kinematics(params, moved, pose, options);
    moved[i] = q[i];
    if (!plus.ok() || !minus.ok()) return false;
    J_pose_actuators.col(i).head<3>() = (plus.pose.translation - minus.pose.translation) / (2 * h);
    J_pose_actuators.col(i).tail<3>() =
        log_so3(plus.pose.rotation * minus.pose.rotation.transpose()) / (2 * h);
  }
  return J_pose_actuators.allFinite();
}

bool Mechanism::nearer_equivalent(const ParamsRef&, const ParamsRef&, const std::vector<bool>&,
                                  const VectorXd&, VectorXd&, std::string*) const {
  return false;
}

}  // namespace kincal
