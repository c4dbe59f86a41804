#pragma once
// What every serial chain shares, whatever its link parametrisation (the DH/Hayati arm, the
// URDF arm): the Jacobian columns of elementary motions, the columns of a six-parameter frame
// block, the frame parameters' names, and the inverse kinematics.
//
// Jacobian columns are built in the "moment" form while walking from base to tool: a rotation
// about the unit axis w through the point o is the column [o x w; w], a translation along u is
// [u; 0]; once the end's position t_end is known, finish_columns() adds w x t_end to the
// translation rows, giving the end's motion [w x (t_end - o); w]. One pass, no 3 x n product.

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "kincal/framework/kinematics/mechanism.hpp"
#include "kincal/framework/kinematics/parameters.hpp"
#include "kincal/framework/kinematics/pose.hpp"

namespace kincal {

/// Options of serial_chain::inverse_kinematics (SerialArm::inverse_kinematics_from,
/// UrdfArm::inverse_kinematics_from).
struct SerialInverseKinematicsOptions {
  int max_iterations = 200;
  /// Solved when the position error is below this (mm) and the rotation error below
  /// rotation_tolerance (rad).
  double position_tolerance = 1e-9;
  double rotation_tolerance = 1e-12;
  /// Rotation errors are weighted by this length (mm per rad) against position errors, so
  /// that 1 mrad counts like 1 mm at 1 m.
  double rotation_weight = 1000.0;
};

namespace serial_chain {

/// The column of a rotation about the unit axis w through o, in the moment form.
template <class Column>
void rotation_column(Column&& column, const Vector3d& w, const Vector3d& o) {
  column.template head<3>() = o.cross(w);
  column.template tail<3>() = w;
}

/// The column of a translation along `direction`.
template <class Column>
void translation_column(Column&& column, const Vector3d& direction) {
  column.template head<3>() = direction;
  column.template tail<3>().setZero();
}

/// Adds w x t_end to the translation rows of every column (nothing for translations, whose w
/// is zero). Column by column: a 3 x 3 times 3 x n product would go through Eigen's general
/// product, which may allocate.
inline void finish_columns(Eigen::Ref<Matrix6Xd>& J, const Vector3d& t_end) {
  for (Eigen::Index c = 0; c < J.cols(); ++c) J.col(c).head<3>() += J.col(c).tail<3>().cross(t_end);
}

/// The six columns of a frame block (x, y, z, then Z-Y-X Euler angles `angles`) that follows
/// the frame `parent` and ends at `after`: its translations move everything beyond it along
/// the parent's axes; its angles turn everything beyond it about parent.R E(angles) through
/// the block's own origin (after's).
template <class Block>
void frame_block_columns(Block&& J, const Pose& parent, const Pose& after, const Vector3d& angles) {
  J.template topLeftCorner<3, 3>() = parent.rotation;
  J.template bottomLeftCorner<3, 3>().setZero();
  const Matrix3d W = parent.rotation * euler_zyx_angular_jacobian(angles);
  for (int k = 0; k < 3; ++k) rotation_column(J.col(3 + k), W.col(k), after.translation);
}

/// Appends a frame block's six parameters, `prefix`.x, .y, .z (mm), .rx, .ry, .rz (rad).
void add_frame_parameters(std::vector<Parameter>& out, const std::string& prefix,
                          const Vector6d& values);

/// The joint values that put a chain's end at `target`, by Levenberg-Marquardt on the
/// weighted pose error [t_target - t; w log(R_target R^T)], from `start`. `pose_at(q)` is
/// the end's pose; `joint_jacobian(q, J)` fills the 6 x n J_pose_q and returns the pose.
/// An unreachable target is a status with a reason and the closest joint values found.
template <class PoseAt, class JointJacobian>
InverseKinematicsResult inverse_kinematics(const Pose& target, const ActuatorsRef& start,
                                           Eigen::Ref<VectorXd> q,
                                           const SerialInverseKinematicsOptions& options,
                                           PoseAt&& pose_at, JointJacobian&& joint_jacobian);

/// The weighted pose error [t_target - t; w log(R_target R^T)]: the perturbation (pose.hpp)
/// that takes the current pose to the target, rotation scaled to mm.
Vector6d pose_error(const Pose& target, const Pose& current, double rotation_weight);
/// "0.1 mm and 0.002 rad": the size of a pose error, in words.
std::string pose_error_text(const Vector6d& e, double rotation_weight);
/// The reason of an inverse kinematics that stopped short (see inverse_kinematics).
void describe_inverse_kinematics_failure(InverseKinematicsResult& result, const Vector6d& e,
                                         double rotation_weight, int joints, bool stationary);

template <class PoseAt, class JointJacobian>
InverseKinematicsResult inverse_kinematics(const Pose& target, const ActuatorsRef& start,
                                           Eigen::Ref<VectorXd> q,
                                           const SerialInverseKinematicsOptions& options,
                                           PoseAt&& pose_at, JointJacobian&& joint_jacobian) {
  InverseKinematicsResult result;
  const auto n = start.size();
  if (!target.rotation.allFinite() || !target.translation.allFinite() || !start.allFinite()) {
    result.status = InverseKinematicsStatus::kNonFinite;
    q = start;
    return result;
  }
  const double w = options.rotation_weight;
  const auto solved = [&](const Vector6d& e) {
    return e.head<3>().norm() <= options.position_tolerance &&
           e.tail<3>().norm() <= w * options.rotation_tolerance;
  };
  Matrix6Xd J(6, n);
  VectorXd x = start, trial(n), step(n);
  MatrixXd A(n, n);
  VectorXd g(n);
  Vector6d e = pose_error(target, joint_jacobian(x, J), w);
  double cost = e.squaredNorm();
  double lambda = -1;  // set from the first Jacobian's scale
  bool stationary = false;
  for (result.iterations = 0; result.iterations < options.max_iterations && !solved(e);
       ++result.iterations) {
    J.bottomRows<3>() *= w;
    A.noalias() = J.transpose() * J;
    g.noalias() = J.transpose() * e;
    const double scale = A.diagonal().maxCoeff();
    if (!(scale > 0) || !std::isfinite(scale)) {  // no joint moves the end: nothing to do
      stationary = true;
      break;
    }
    if (lambda < 0) lambda = 1e-3 * scale;
    // Grow the damping until a step lowers the cost. A cost that no step lowers, even tiny,
    // is a stationary point of the pose error.
    bool accepted = false;
    while (!accepted) {
      A.diagonal().array() += lambda;
      step = A.ldlt().solve(g);
      A.diagonal().array() -= lambda;
      trial = x + step;
      const double cost_trial = pose_error(target, pose_at(trial), w).squaredNorm();
      if (cost_trial < cost) {
        accepted = true;
        x = trial;
        lambda = std::max(lambda / 3, 1e-12 * scale);
        if (step.norm() <= 1e-15 * (1 + x.norm()) || cost - cost_trial <= 1e-15 * cost)
          stationary = true;
      } else {
        lambda *= 4;
        if (lambda > 1e12 * scale) {
          stationary = true;
          break;
        }
      }
    }
    e = pose_error(target, joint_jacobian(x, J), w);
    cost = e.squaredNorm();
    if (stationary && !solved(e)) break;
  }
  q = x;  // the solution, or the closest joint values found
  result.residual_norm = e.head<3>().norm() + e.tail<3>().norm() / w;
  if (!solved(e))
    describe_inverse_kinematics_failure(result, e, w, static_cast<int>(n), stationary);
  return result;
}

}  // namespace serial_chain
}  // namespace kincal
