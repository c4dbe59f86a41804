#pragma once
// The pose convention of `kincal fk` and `kincal ik`, shared so both print the same.

namespace kincal::cli {

inline constexpr const char* kPoseConvention =
    "pose = x,y,z,rx,ry,rz: position of the platform frame in the base frame (mm) and Z-Y-X "
    "Euler angles in degrees, R = Rz(rz) Ry(ry) Rx(rx) (rotate about x, then y, then z, all "
    "fixed base axes); a platform point p is at R p + t in the base frame";

}  // namespace kincal::cli
