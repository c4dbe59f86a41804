#pragma once
// The column names under which a measurement file may give an orientation reading, for any
// sensor whose readings include a rotation vector (the pose tracker; a plug-in's own): the
// rotation vector itself (<prefix>.rotvec_x, _y, _z), roll-pitch-yaw angles (<prefix>.roll,
// .pitch, .yaw: R = Rz(yaw) Ry(pitch) Rx(roll), fixed axes x, y, z in that order, as URDF's
// rpy), or a unit quaternion (<prefix>.qw, .qx, .qy, .qz). Names that do not say which
// (<prefix>.rx, .ry, .rz: a UR controller's rotation vector, or Euler angles in most other
// vendors' files) are refused: read as the wrong convention they fit a wrong orientation
// without any other sign of it.

#include <string>
#include <vector>

#include "kincal/framework/kinematics/sensor.hpp"

namespace kincal {

/// The rotation vector's reading names: <prefix>.rotvec_x, <prefix>.rotvec_y, <prefix>.rotvec_z.
std::vector<std::string> rotation_vector_names(const std::string& prefix);

/// Roll-pitch-yaw and quaternion columns for the rotation vector readings first_reading ..
/// first_reading + 2 of a sensor.
std::vector<ReadingColumns> orientation_alternatives(const std::string& prefix, int first_reading);

/// <prefix>.rx, .ry, .rz, refused with what to name them instead.
RefusedColumns ambiguous_orientation_columns(const std::string& prefix);

/// A quaternion whose length differs from 1 by more than this is not a rotation (a wrong
/// column, or a value of another kind); within it, it is normalised.
constexpr double kQuaternionNormTolerance = 1e-3;

}  // namespace kincal
