#pragma once
// What the URDF arm's tests share: frames and joints written as in a URDF, and forward
// kinematics as the URDF defines it, a product of Isometry3d independent of UrdfArm.

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "kincal/models/urdf_arm.hpp"

namespace kincal::testing {

inline Vector6d frame6(double x, double y, double z, double rx, double ry, double rz) {
  Vector6d f;
  f << x, y, z, rx, ry, rz;
  return f;
}

inline UrdfArmJoint joint(const std::string& name, UrdfJointType type, const Vector6d& origin,
                          const Vector3d& axis) {
  UrdfArmJoint j;
  j.name = name;
  j.type = type;
  j.origin = origin;
  j.axis = axis;
  j.lower = type == UrdfJointType::kPrismatic ? -200 : -3;
  j.upper = -j.lower;
  if (type == UrdfJointType::kContinuous) j.lower = j.upper = NAN;
  return j;
}

// FK as the URDF defines it, independently of serial_chain::walk: a product of Isometry3d.
inline Eigen::Isometry3d independent_fk(const UrdfArmGeometry& g, const VectorXd& q) {
  auto iso = [](const Vector6d& f) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = f.head<3>();
    T.linear() =
        (Eigen::AngleAxisd(f[5], Vector3d::UnitZ()) * Eigen::AngleAxisd(f[4], Vector3d::UnitY()) *
         Eigen::AngleAxisd(f[3], Vector3d::UnitX()))
            .toRotationMatrix();
    return T;
  };
  Eigen::Isometry3d T = iso(g.base);
  for (std::size_t i = 0; i < g.joints.size(); ++i) {
    const UrdfArmJoint& j = g.joints[i];
    T = T * iso(j.origin) * iso(j.origin_error);
    const double v = q[static_cast<int>(i)] + j.offset;
    if (j.type == UrdfJointType::kPrismatic)
      T = T * Eigen::Translation3d(v * j.axis.normalized());
    else
      T = T * Eigen::AngleAxisd(v, j.axis.normalized());
  }
  return T * iso(g.tip) * iso(g.tool);
}

}  // namespace kincal::testing
