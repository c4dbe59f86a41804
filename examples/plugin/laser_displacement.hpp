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
//
// The reading is written once, as a function template (autodiff_readings): AutoDiffSensor
// derives J_reading_pose and J_reading_params from it by automatic differentiation
// (kincal/framework/kinematics/autodiff.hpp), the azimuth/elevation derivatives included. A beam
// that runs (nearly) parallel to the plane, or meets it behind the laser, gives no reading: the
// sensor says so (reads_at), and that reading is dropped for that configuration.

#include <kincal/framework/kinematics/autodiff.hpp>
#include <kincal/framework/kinematics/sensor.hpp>

namespace five_bar_plugin {

struct LaserGeometry {
  kincal::Vector3d origin = kincal::Vector3d::Zero();
  double azimuth = 0, elevation = 0;              ///< of the beam, base frame (rad)
  double plane_azimuth = 0, plane_elevation = 0;  ///< of the plane's normal, platform frame
  double plane_distance = 0;                      ///< of the plane from the platform origin
};

class LaserDisplacement final : public kincal::AutoDiffSensor<LaserDisplacement, 8, 1> {
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

  /// reading = (h + n . (t - s)) / (n . u), for any scalar T.
  template <class T>
  void autodiff_readings(const T* p, const kincal::PoseT<T>& pose, T* reading) const {
    const Eigen::Matrix<T, 3, 1> u = unit_vector(p[kAzimuth], p[kElevation]);
    const Eigen::Matrix<T, 3, 1> n =
        pose.rotation * unit_vector(p[kPlaneAzimuth], p[kPlaneElevation]);
    T along = p[kPlaneDistance];
    for (int i = 0; i < 3; ++i) along += n[i] * (pose.translation[i] - p[kOriginX + i]);
    reading[0] = along / n.dot(u);
  }

  bool can_miss() const override { return true; }
  bool reads_at(const Eigen::Ref<const kincal::VectorXd>& params, const kincal::Pose& pose,
                std::string* reason) const override;

  /// (cos el cos az, cos el sin az, sin el).
  template <class T>
  static Eigen::Matrix<T, 3, 1> unit_vector(const T& azimuth, const T& elevation) {
    using std::cos;
    using std::sin;
    return Eigen::Matrix<T, 3, 1>(cos(elevation) * cos(azimuth), cos(elevation) * sin(azimuth),
                                  sin(elevation));
  }

 private:
  std::string name_;
  std::vector<kincal::Parameter> parameters_;
};

}  // namespace five_bar_plugin
