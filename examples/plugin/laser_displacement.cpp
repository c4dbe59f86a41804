#include "laser_displacement.hpp"

#include <cmath>
#include <kincal/framework/units.hpp>

namespace five_bar_plugin {

using namespace kincal;

namespace {

Vector3d unit_vector(double azimuth, double elevation) {
  return Vector3d(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                  std::sin(elevation));
}
Vector3d d_unit_d_azimuth(double azimuth, double elevation) {
  return Vector3d(-std::cos(elevation) * std::sin(azimuth), std::cos(elevation) * std::cos(azimuth),
                  0.0);
}
Vector3d d_unit_d_elevation(double azimuth, double elevation) {
  return Vector3d(-std::sin(elevation) * std::cos(azimuth),
                  -std::sin(elevation) * std::sin(azimuth), std::cos(elevation));
}

// The reading's parts: r = N / D with N = h + n . (t - s), D = n . u.
struct Beam {
  Vector3d u, n, n_platform, to_platform;  // to_platform = t - s
  double N, D;
};

Beam beam(const Eigen::Ref<const VectorXd>& p, const Pose& pose) {
  using L = LaserDisplacement;
  Beam b;
  b.u = unit_vector(p[L::kAzimuth], p[L::kElevation]);
  b.n_platform = unit_vector(p[L::kPlaneAzimuth], p[L::kPlaneElevation]);
  b.n = pose.rotation * b.n_platform;
  b.to_platform = pose.translation - p.segment<3>(L::kOriginX);
  b.N = p[L::kPlaneDistance] + b.n.dot(b.to_platform);
  b.D = b.n.dot(b.u);
  return b;
}

// The Jacobians, one function each, written by hand (each is held to finite differences by
// `kincal check`). d r / d n, used by both.
Vector3d d_reading_d_normal(const Beam& b) { return b.to_platform / b.D - b.N / (b.D * b.D) * b.u; }

// d r / d [dt; dw]: t moves the plane along n; a rotation dw turns n by dw x n, and
// g . (dw x n) = dw . (n x g).
Eigen::Matrix<double, 1, 6> reading_jacobian_pose(const Beam& b) {
  Eigen::Matrix<double, 1, 6> J;
  J << (b.n / b.D).transpose(), b.n.cross(d_reading_d_normal(b)).transpose();
  return J;
}

Eigen::Matrix<double, 1, LaserDisplacement::kCount> reading_jacobian_params(
    const Eigen::Ref<const VectorXd>& p, const Pose& pose, const Beam& b) {
  using L = LaserDisplacement;
  Eigen::Matrix<double, 1, L::kCount> J;
  J.segment<3>(L::kOriginX) = (-b.n / b.D).transpose();
  const Vector3d d_r_d_u = -b.N / (b.D * b.D) * b.n;
  J[L::kAzimuth] = d_r_d_u.dot(d_unit_d_azimuth(p[L::kAzimuth], p[L::kElevation]));
  J[L::kElevation] = d_r_d_u.dot(d_unit_d_elevation(p[L::kAzimuth], p[L::kElevation]));
  const Vector3d d_r_d_n_platform = pose.rotation.transpose() * d_reading_d_normal(b);
  J[L::kPlaneAzimuth] =
      d_r_d_n_platform.dot(d_unit_d_azimuth(p[L::kPlaneAzimuth], p[L::kPlaneElevation]));
  J[L::kPlaneElevation] =
      d_r_d_n_platform.dot(d_unit_d_elevation(p[L::kPlaneAzimuth], p[L::kPlaneElevation]));
  J[L::kPlaneDistance] = 1.0 / b.D;
  return J;
}

}  // namespace

LaserDisplacement::LaserDisplacement(std::string name, const LaserGeometry& g)
    : name_(std::move(name)) {
  parameters_ = {{name_ + ".origin.x", g.origin.x(), kMillimetre},
                 {name_ + ".origin.y", g.origin.y(), kMillimetre},
                 {name_ + ".origin.z", g.origin.z(), kMillimetre},
                 {name_ + ".azimuth", g.azimuth, kRadian},
                 {name_ + ".elevation", g.elevation, kRadian},
                 {name_ + ".plane.azimuth", g.plane_azimuth, kRadian},
                 {name_ + ".plane.elevation", g.plane_elevation, kRadian},
                 {name_ + ".plane.distance", g.plane_distance, kMillimetre}};
}

void LaserDisplacement::predict(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                                Eigen::Ref<VectorXd> reading, MatrixXd* J_reading_pose,
                                MatrixXd* J_reading_params) const {
  const Beam b = beam(params, pose);
  reading[0] = b.N / b.D;  // D = 0 (beam parallel to the plane) gives +-inf or NaN
  if (J_reading_pose) *J_reading_pose = reading_jacobian_pose(b);
  if (J_reading_params) *J_reading_params = reading_jacobian_params(params, pose, b);
}

}  // namespace five_bar_plugin
