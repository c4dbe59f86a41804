#include "kincal/models/presets.hpp"

#include <stdexcept>

#include "kincal/framework/model_registry.hpp"
#include "kincal/models/hexapod.hpp"
#include "kincal/models/length_gauge.hpp"

namespace kincal {

std::vector<PresetInfo> list_presets() {
  std::vector<PresetInfo> out;
  for (const auto& p : ModelRegistry::global().presets()) out.push_back({p.name, p.description});
  return out;
}

std::shared_ptr<MeasurementModel> make_preset(const std::string& name) {
  return ModelRegistry::global().make_preset(name);
}

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

}  // namespace kincal
