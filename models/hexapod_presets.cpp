// The hexapod presets: nominal geometries from the literature, each with its sensors and a
// default free mask that a default simulation can determine.

#include "kincal/models/hexapod.hpp"
#include "kincal/models/length_gauge.hpp"
#include "kincal/models/presets.hpp"

namespace kincal {

std::shared_ptr<MeasurementModel> make_cube_hexapod() {
  // Table 1 of the paper, mm.
  HexapodGeometry g;
  g.base_joints = {Vector3d(-140, -140, 28), Vector3d(-140, 140, 28), Vector3d(140, 0, 28),
                   Vector3d(177, 70, 130),   Vector3d(177, -70, 130), Vector3d(0, -205, 280)};
  g.platform_joints = {Vector3d(-140, -140, -28), Vector3d(-140, 140, -28),
                       Vector3d(140, 0, -28),     Vector3d(-177, 70, -280),
                       Vector3d(-177, -70, -280), Vector3d(0, 177, -140)};
  g.home.translation = Vector3d(0, 0, 410);
  auto hexapod = std::make_shared<Hexapod>(g);
  auto gauge =
      std::make_shared<LengthGauge>("gauge", Vector3d(-200, 500, 500), Vector3d(-200, 205, -5));
  auto model = std::make_shared<MeasurementModel>(
      hexapod, std::vector<std::shared_ptr<const Sensor>>{gauge});
  // The paper identifies x, y, z of legs 4-6 and z of legs 1-3, base and platform joints.
  for (int leg = 4; leg <= 6; ++leg) {
    model->parameters().set_free("leg" + std::to_string(leg) + ".base.?", true);
    model->parameters().set_free("leg" + std::to_string(leg) + ".platform.?", true);
  }
  for (int leg = 1; leg <= 3; ++leg) {
    model->parameters().set_free("leg" + std::to_string(leg) + ".base.z", true);
    model->parameters().set_free("leg" + std::to_string(leg) + ".platform.z", true);
  }
  return model;
}

std::shared_ptr<MeasurementModel> make_stewart_6_6() {
  // Nominal values of Table 1 of M. J. Nategh and M. M. Agheli, "A total solution to kinematic
  // calibration of hexapod machine tools with a minimum number of measurement configurations
  // and superior accuracies" (2009), mm: base joints on a circle of radius 325 at 20, 100,
  // 140, 220, 260 and 340 degrees, platform joints on a circle of radius 125 at 42.5, 77.5,
  // 162.5, 197.5, 282.5 and 317.5 degrees, both in their z = 0 planes; every leg 604.8652 mm
  // long at zero actuator stroke (the leg offsets).
  HexapodGeometry g;
  g.base_joints = {Vector3d(305.4001, 111.1565, 0),  Vector3d(-56.4357, 320.0625, 0),
                   Vector3d(-248.9644, 208.9060, 0), Vector3d(-248.9644, -208.9060, 0),
                   Vector3d(-56.4357, -320.0625, 0), Vector3d(305.4001, -111.1565, 0)};
  g.platform_joints = {Vector3d(92.1597, 84.4488, 0),   Vector3d(27.0550, 122.0370, 0),
                       Vector3d(-119.2146, 37.5882, 0), Vector3d(-119.2146, -37.5882, 0),
                       Vector3d(27.0550, -122.0370, 0), Vector3d(92.1597, -84.4488, 0)};
  g.leg_offsets.fill(604.8652);
  // Every leg is at its offset length, zero stroke, 565.40 mm above the base, level.
  g.home.translation = Vector3d(0, 0, 565.4);
  auto hexapod = std::make_shared<Hexapod>(g);
  // One draw-wire gauge from a stand beside the machine to the platform's edge. Its points
  // and the platform joints fix the frames; the free set is what a strut machine's assembly
  // leaves uncertain: the six strut reference lengths and where the base joints sit in the
  // floor plane. A distance cannot see a turn of the base frame about the vertical through
  // the gauge's base point: leg1.base.x fixes it. 17 free parameters.
  auto gauge = std::make_shared<LengthGauge>("gauge", Vector3d(0, -600, 300), Vector3d(0, -100, 0));
  auto model = std::make_shared<MeasurementModel>(
      hexapod, std::vector<std::shared_ptr<const Sensor>>{gauge});
  model->parameters().set_free("leg*.offset", true);
  model->parameters().set_free("leg*.base.x", true);
  model->parameters().set_free("leg*.base.y", true);
  model->parameters().set_free("leg1.base.x", false);
  return model;
}

}  // namespace kincal
