#pragma once
// Rigid poses and the one perturbation convention used by every Jacobian.
//
// A pose maps platform coordinates to base coordinates: x_base = R x_platform + t.
// A perturbation is a 6-vector delta = [dt; dw] (mm, rad), applied as
//   t <- t + dt,   R <- exp([dw]x) R
// i.e. translation first, rotation as a small rotation about base-frame axes applied on
// the left. See docs/theory.md.

#include "kincal/framework/types.hpp"

namespace kincal {

struct Pose {
  Matrix3d rotation = Matrix3d::Identity();
  Vector3d translation = Vector3d::Zero();

  Vector3d transform_point(const Vector3d& p) const { return rotation * p + translation; }
};

/// [v]x, the cross-product matrix: skew(v) * u == v.cross(u).
Matrix3d skew(const Vector3d& v);

/// Rotation matrix of the rotation vector w (Rodrigues' formula), exact for all angles.
Matrix3d exp_so3(const Vector3d& w);

/// Rotation vector of R (inverse of exp_so3), angle in [0, pi].
Vector3d log_so3(const Matrix3d& R);

/// The pose perturbed by delta = [dt; dw] under the convention above.
Pose perturb(const Pose& pose, const Vector6d& delta);

/// Z-Y-X Euler angles (alpha, beta, gamma) with R = Rz(alpha) Ry(beta) Rx(gamma).
Vector3d euler_zyx(const Matrix3d& R);

/// R = Rz(alpha) Ry(beta) Rx(gamma).
Matrix3d rotation_from_euler_zyx(const Vector3d& alpha_beta_gamma);

/// Position error |t_a - t_b| (mm) between two poses.
double position_error(const Pose& a, const Pose& b);

/// Orientation error of the paper: sqrt(alpha^2 + beta^2 + gamma^2) of the Z-Y-X Euler angles
/// of R_reference^T R_other (rad).
double orientation_error(const Pose& reference, const Pose& other);

}  // namespace kincal
