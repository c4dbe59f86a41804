#pragma once
// Rigid poses and the one perturbation convention used by every Jacobian.
//
// A pose maps platform coordinates to base coordinates: x_base = R x_platform + t.
// A perturbation is a 6-vector delta = [dt; dw] (mm, rad), applied as
//   t <- t + dt,   R <- exp([dw]x) R
// i.e. translation first, rotation as a small rotation about base-frame axes applied on
// the left. See docs/theory.md.

#include "kincal/framework/base/types.hpp"

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

/// Left Jacobian of SO(3): exp(w + e) = exp(J_l(w) e) exp(w) to first order in e, i.e. how
/// the rotation vector's increment shows as a left (base-axes) perturbation.
///   J_l(w) = I + (1 - cos t) / t^2 [w]x + (t - sin t) / t^3 [w]x^2,  t = |w|.
Matrix3d left_jacobian_so3(const Vector3d& w);

/// Inverse of the left Jacobian: log(exp(d) exp(w)) = w + J_l^-1(w) d to first order in d,
/// the exact derivative of log_so3 under a left perturbation (a rotation error's Jacobian).
///   J_l^-1(w) = I - [w]x / 2 + (1 / t^2 - (1 + cos t) / (2 t sin t)) [w]x^2.
/// Unbounded as t -> pi, where the rotation vector flips (log is not smooth there).
Matrix3d left_jacobian_inverse_so3(const Vector3d& w);

/// The pose perturbed by delta = [dt; dw] under the convention above.
Pose perturb(const Pose& pose, const Vector6d& delta);

/// a * b: the frame b given in a's coordinates, in a's parent's. Inline: the chains' walks
/// compose a few frames per link and configuration, and a call per frame was 12 % of a
/// calibration of a URDF arm (issue 37).
inline Pose compose(const Pose& a, const Pose& b) {
  Pose c;
  c.rotation = a.rotation * b.rotation;
  c.translation = a.translation + a.rotation * b.translation;
  return c;
}
/// The inverse rigid motion: compose(p, inverse(p)) is the identity.
Pose inverse(const Pose& p);

/// Z-Y-X Euler angles (alpha, beta, gamma) with R = Rz(alpha) Ry(beta) Rx(gamma).
Vector3d euler_zyx(const Matrix3d& R);

/// R = Rz(alpha) Ry(beta) Rx(gamma).
Matrix3d rotation_from_euler_zyx(const Vector3d& alpha_beta_gamma);

/// A frame given by six parameters [x, y, z, rx, ry, rz] (mm, rad): position, and Z-Y-X
/// Euler angles R = Rz(rz) Ry(ry) Rx(rx), the form of every frame parameter block (a serial
/// arm's base and tool, a tracker's frame).
Pose frame_from_parameters(const Eigen::Ref<const VectorXd>& xyz_rxryrz);
/// The inverse: [x, y, z, rx, ry, rz] of a frame.
Vector6d frame_parameters(const Pose& frame);
/// Columns: the angular velocity [dw] (left perturbation, parent axes) of R = Rz Ry Rx per
/// unit rate of rx, ry and rz. Singular at ry = +-90 degrees (gimbal lock).
Matrix3d euler_zyx_angular_jacobian(const Vector3d& rx_ry_rz);

/// A frame parameter block's frame (frame_from_parameters) and the angular Jacobian of its
/// angles (euler_zyx_angular_jacobian).
struct FrameBlock {
  Pose frame;
  Matrix3d angular_jacobian;
};
/// frame_from_parameters and euler_zyx_angular_jacobian of the six values at `xyz_rxryrz`,
/// exactly, remembered per thread for the blocks seen last (by their values' bits): a
/// calibration evaluates the same few blocks (a base, a tool, an origin error per joint, a
/// tracker's frame) at every configuration of one parameter vector, and each costs five
/// sines and cosines.
FrameBlock frame_block(const double* xyz_rxryrz);
/// The same for a block of a vector (six contiguous values).
template <class Block>
FrameBlock frame_block(const Block& xyz_rxryrz) {
  static_assert(Block::SizeAtCompileTime == 6 || Block::SizeAtCompileTime == Eigen::Dynamic);
  return frame_block(xyz_rxryrz.data());
}

/// Position error |t_a - t_b| (mm) between two poses.
double position_error(const Pose& a, const Pose& b);

/// Orientation error of the paper: sqrt(alpha^2 + beta^2 + gamma^2) of the Z-Y-X Euler angles
/// of R_reference^T R_other (rad).
double orientation_error(const Pose& reference, const Pose& other);

}  // namespace kincal
