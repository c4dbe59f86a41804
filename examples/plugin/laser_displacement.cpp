#include "laser_displacement.hpp"

#include <cmath>
#include <kincal/framework/kinematics/units.hpp>

namespace five_bar_plugin {

using namespace kincal;

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

bool LaserDisplacement::reads_at(const Eigen::Ref<const VectorXd>& p, const Pose& pose,
                                 std::string* reason) const {
  const Vector3d u = unit_vector(p[kAzimuth], p[kElevation]);
  const Vector3d n = pose.rotation * unit_vector(p[kPlaneAzimuth], p[kPlaneElevation]);
  // Below 1e-6 the distance (and its derivatives) blow up: a grazing beam reads nothing.
  const double incidence = n.dot(u);
  if (!(std::abs(incidence) > 1e-6)) {
    if (reason) *reason = "the beam runs parallel to the plane";
    return false;
  }
  const double distance =
      (p[kPlaneDistance] + n.dot(pose.translation - p.segment<3>(kOriginX))) / incidence;
  if (!(distance > 0)) {
    if (reason) *reason = "the plane is behind the laser";
    return false;
  }
  return true;
}

}  // namespace five_bar_plugin
