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

namespace {

// LU with partial pivoting of a 6 x 6 matrix, with loops of fixed trip count the compiler
// unrolls. Eigen's PartialPivLU<Matrix6d> runs its generic blocked code and was the largest
// single cost of forward kinematics (see docs/benchmarks.md). No allocation.
class Lu6 {
 public:
  explicit Lu6(const Matrix6d& a) : lu_(a) {
    for (int i = 0; i < 6; ++i) perm_[i] = i;
    for (int k = 0; k < 6; ++k) {
      int p = k;
      for (int i = k + 1; i < 6; ++i)
        if (std::abs(lu_(i, k)) > std::abs(lu_(p, k))) p = i;
      if (p != k) {
        lu_.row(k).swap(lu_.row(p));
        std::swap(perm_[k], perm_[p]);
      }
      const double pivot = lu_(k, k);
      inverse_pivots_[k] = 1.0 / pivot;
      if (pivot == 0.0) continue;  // singular: near_singular() says so
      for (int i = k + 1; i < 6; ++i) {
        const double f = lu_(i, k) *= inverse_pivots_[k];
        for (int j = k + 1; j < 6; ++j) lu_(i, j) -= f * lu_(k, j);
      }
    }
  }

  Vector6d solve(const Vector6d& b) const {
    Vector6d y;
    for (int i = 0; i < 6; ++i) {
      double sum = b[perm_[i]];
      for (int j = 0; j < i; ++j) sum -= lu_(i, j) * y[j];
      y[i] = sum;
    }
    for (int i = 5; i >= 0; --i) {
      double sum = y[i];
      for (int j = i + 1; j < 6; ++j) sum -= lu_(i, j) * y[j];
      y[i] = sum * inverse_pivots_[i];
    }
    return y;
  }

  Matrix6d inverse() const {
    Matrix6d inv;
    for (int c = 0; c < 6; ++c) inv.col(c) = solve(Vector6d::Unit(c));
    return inv;
  }

  // Whether `a`, the matrix factored, is singular: a tiny reciprocal condition number. Eigen's L1
  // rcond estimate costs several solves, a third of a forward kinematics solve when asked every
  // iteration: it is only asked when the pivots already spread over four decades (cond(A) is
  // at least max|u_ii| / min|u_ii|, and partial pivoting does not hide an rcond near 1e-12
  // behind well-spread pivots in the 6 x 6 Jacobians of real mechanisms).
  bool near_singular(const Matrix6d& a) const {
    const Vector6d pivots = lu_.diagonal().cwiseAbs();
    if (!(pivots.prod() > 1e-300)) return true;
    if (pivots.minCoeff() > 1e-4 * pivots.maxCoeff()) return false;
    return Eigen::PartialPivLU<Matrix6d>(a).rcond() < 1e-12;
  }

 private:
  // Row-major: pivoting swaps and eliminates rows, which are then contiguous.
  Eigen::Matrix<double, 6, 6, Eigen::RowMajor> lu_;
  Vector6d inverse_pivots_;
  int perm_[6];
};

}  // namespace

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
    const Lu6 lu(J_g_pose);
    if (lu.near_singular(J_g_pose)) {
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
  // One inverse and fixed-size products beat a solve per parameter column (42 of them for a
  // hexapod). Column by column with a fixed-size temporary: no heap allocation.
  const Matrix6d minus_inverse = -Lu6(J_g_pose).inverse();
  for (Eigen::Index c = 0; c < J_pose_params.cols(); ++c) {
    const Vector6d column = J_pose_params.col(c);
    J_pose_params.col(c).noalias() = minus_inverse * column;
  }
}

}  // namespace kincal
