#include "framework/pose.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace kincal {

Matrix3d skew(const Vector3d& v) {
  Matrix3d S;
  S << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return S;
}

Matrix3d exp_so3(const Vector3d& w) {
  const double angle = w.norm();
  if (angle < 1e-12) return Matrix3d::Identity() + skew(w);
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

Vector3d log_so3(const Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

Pose perturb(const Pose& pose, const Vector6d& delta) {
  Pose out;
  out.translation = pose.translation + delta.head<3>();
  out.rotation = exp_so3(delta.tail<3>()) * pose.rotation;
  return out;
}

Vector3d euler_zyx(const Matrix3d& R) {
  // R = Rz(a) Ry(b) Rx(g): R(2,0) = -sin b, R(1,0)/R(0,0) = tan a, R(2,1)/R(2,2) = tan g.
  const double beta = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  const double alpha = std::atan2(R(1, 0), R(0, 0));
  const double gamma = std::atan2(R(2, 1), R(2, 2));
  return Vector3d(alpha, beta, gamma);
}

Matrix3d rotation_from_euler_zyx(const Vector3d& abg) {
  return (Eigen::AngleAxisd(abg.x(), Vector3d::UnitZ()) *
          Eigen::AngleAxisd(abg.y(), Vector3d::UnitY()) *
          Eigen::AngleAxisd(abg.z(), Vector3d::UnitX()))
      .toRotationMatrix();
}

double position_error(const Pose& a, const Pose& b) {
  return (a.translation - b.translation).norm();
}

double orientation_error(const Pose& reference, const Pose& other) {
  return euler_zyx(reference.rotation.transpose() * other.rotation).norm();
}

}  // namespace kincal
