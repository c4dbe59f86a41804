#include "kincal/framework/kinematics/orientation_columns.hpp"

#include <cmath>
#include <cstdio>

#include "kincal/framework/kinematics/pose.hpp"

namespace kincal {

std::vector<std::string> rotation_vector_names(const std::string& prefix) {
  return {prefix + ".rotvec_x", prefix + ".rotvec_y", prefix + ".rotvec_z"};
}

std::vector<ReadingColumns> orientation_alternatives(const std::string& prefix, int first_reading) {
  ReadingColumns rpy;
  rpy.convention = "roll-pitch-yaw (R = Rz(yaw) Ry(pitch) Rx(roll))";
  rpy.first_reading = first_reading;
  rpy.readings = 3;
  rpy.columns = {prefix + ".roll", prefix + ".pitch", prefix + ".yaw"};
  rpy.units = {"rad", "rad", "rad"};
  rpy.convert = [](const double* v, double* readings, std::string*) {
    const Vector3d w = log_so3(rotation_from_euler_zyx(Vector3d(v[2], v[1], v[0])));
    for (int i = 0; i < 3; ++i) readings[i] = w[i];
    return true;
  };
  ReadingColumns quaternion;
  quaternion.convention = "quaternion (w, x, y, z)";
  quaternion.first_reading = first_reading;
  quaternion.readings = 3;
  quaternion.columns = {prefix + ".qw", prefix + ".qx", prefix + ".qy", prefix + ".qz"};
  quaternion.units = {"", "", "", ""};
  quaternion.convert = [](const double* v, double* readings, std::string* why) {
    const Eigen::Quaterniond q(v[0], v[1], v[2], v[3]);
    const double norm = q.norm();
    if (!(std::abs(norm - 1) <= kQuaternionNormTolerance)) {
      if (why) {
        char text[160];
        std::snprintf(text, sizeof text,
                      "the quaternion's length is %.6g, expected 1 (within %g): not a rotation",
                      norm, kQuaternionNormTolerance);
        *why = text;
      }
      return false;
    }
    const Vector3d w = log_so3(q.normalized().toRotationMatrix());
    for (int i = 0; i < 3; ++i) readings[i] = w[i];
    return true;
  };
  return {rpy, quaternion};
}

RefusedColumns ambiguous_orientation_columns(const std::string& prefix) {
  return {{prefix + ".rx", prefix + ".ry", prefix + ".rz"},
          "rx, ry, rz do not say which orientation they hold (a rotation vector, as a UR "
          "controller reports it, or Euler angles, as most other vendors' files do), and read as "
          "the wrong one they fit a wrong orientation without any other sign; name the columns " +
              prefix + ".rotvec_x, _y, _z for a rotation vector, " + prefix +
              ".roll, .pitch, .yaw for R = Rz(yaw) Ry(pitch) Rx(roll), or " + prefix +
              ".qw, .qx, .qy, .qz for a quaternion (angles may carry _deg)"};
}

}  // namespace kincal
