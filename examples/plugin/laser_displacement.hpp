#pragma once
// A laser displacement sensor, a sensor kincal does not ship: a beam from a point s on the
// base, along the unit direction u (azimuth az, elevation el), to a plane fixed on the
// platform, with normal n_p (platform frame; azimuth and elevation) at distance h from the
// platform origin. It reads the distance along the beam to the plane:
//
//   u = (cos el cos az, cos el sin az, sin el),   n = R n_p
//   reading = (h + n . (t - s)) / (n . u)        (mm)
//
// from n . (s + reading u) = h + n . t, the plane's equation in base coordinates.
// Parameters: <name>.origin.{x,y,z}, <name>.plane.distance (mm), <name>.azimuth,
// <name>.elevation, <name>.plane.azimuth, <name>.plane.elevation (rad).

#include <kincal/framework/sensor.hpp>

namespace five_bar_plugin {

struct LaserGeometry {
  kincal::Vector3d origin = kincal::Vector3d::Zero();
  double azimuth = 0, elevation = 0;              ///< of the beam, base frame (rad)
  double plane_azimuth = 0, plane_elevation = 0;  ///< of the plane's normal, platform frame
  double plane_distance = 0;                      ///< of the plane from the platform origin
};

class LaserDisplacement final : public kincal::Sensor {
 public:
  enum Index {
    kOriginX,
    kOriginY,
    kOriginZ,
    kAzimuth,
    kElevation,
    kPlaneAzimuth,
    kPlaneElevation,
    kPlaneDistance,
    kCount
  };

  LaserDisplacement(std::string name, const LaserGeometry& geometry);

  std::string type() const override { return "laser-displacement"; }
  const std::string& name() const override { return name_; }
  int num_readings() const override { return 1; }
  std::vector<std::string> reading_units() const override { return {kincal::kMillimetre}; }
  const std::vector<kincal::Parameter>& parameters() const override { return parameters_; }

  /// A beam parallel to the plane has no reading: NaN (the residual then fails loudly).
  void predict(const Eigen::Ref<const kincal::VectorXd>& params, const kincal::Pose& pose,
               Eigen::Ref<kincal::VectorXd> reading, kincal::MatrixXd* J_reading_pose,
               kincal::MatrixXd* J_reading_params) const override;

 private:
  std::string name_;
  std::vector<kincal::Parameter> parameters_;
};

}  // namespace five_bar_plugin
