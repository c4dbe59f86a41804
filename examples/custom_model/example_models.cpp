// The example's types in model files, and a preset:
//   "mechanism": { "type": "two-link-arm", "link1": 300, "link2": 200,
//                  "offsets_deg": [0, 0] }
//   { "type": "inclinometer", "name": "tilt", "offset_deg": 0 }

#include "example_models.hpp"

#include <kincal/models/length_gauge.hpp>

#include "inclinometer.hpp"
#include "two_link_arm.hpp"

namespace example {

using namespace kincal;
using namespace kincal::json_field;

namespace {

constexpr double kDegree = M_PI / 180;

std::shared_ptr<const Mechanism> read_arm(const Json& j, const JsonPath& where) {
  check_keys(j, where, {"type", "link1", "link2", "offsets_deg"});
  auto arm = std::make_shared<TwoLinkArm>(number(member(j, "link1", where), where / "link1"),
                                          number(member(j, "link2", where), where / "link2"));
  if (const Json* offsets = optional(j, "offsets_deg")) {
    const JsonPath at = where / "offsets_deg";
    if (!offsets->is_array() || offsets->size() != 2) at.fail("expected [joint1, joint2]");
    // Nominal offsets other than 0 need a mechanism built with them; this small example
    // keeps them at 0 in its files and lets calibration find them.
    for (int i = 0; i < 2; ++i)
      if (number((*offsets)[i], at[i]) != 0) at[i].fail("expected 0 (see example_models.cpp)");
  }
  return arm;
}

Json write_arm(const Mechanism&, const Eigen::Ref<const VectorXd>& values) {
  return {{"link1", values[0]},
          {"link2", values[1]},
          {"offsets_deg", {values[2] / kDegree, values[3] / kDegree}}};
}

std::shared_ptr<const Sensor> read_inclinometer(const Json& j, const JsonPath& where) {
  check_keys(j, where, {"type", "name", "offset_deg"});
  return std::make_shared<Inclinometer>(name(member(j, "name", where), where / "name"),
                                        number_or(j, "offset_deg", 0, where) * kDegree);
}

Json write_inclinometer(const Sensor& sensor, const Eigen::Ref<const VectorXd>& values) {
  return {{"name", sensor.name()}, {"offset_deg", values[0] / kDegree}};
}

std::shared_ptr<MeasurementModel> make_demo() {
  auto arm = std::make_shared<TwoLinkArm>(300, 200);
  // A draw-wire gauge from a post at (600, 0, 0) mm to the arm's tip, and an inclinometer.
  auto gauge = std::make_shared<LengthGauge>("gauge", Vector3d(600, 0, 0), Vector3d::Zero());
  auto tilt = std::make_shared<Inclinometer>("tilt");
  auto model = std::make_shared<MeasurementModel>(
      arm, std::vector<std::shared_ptr<const Sensor>>{gauge, tilt});
  model->parameters().set_free("link?.length", true);
  model->parameters().set_free("joint?.offset", true);
  model->parameters().set_free("tilt.offset", true);
  return model;
}

}  // namespace

void register_example_models(ModelRegistry& registry) {
  registry.add_mechanism(
      {"two-link-arm", "planar arm with two revolute joints (example)", read_arm, write_arm});
  registry.add_sensor({"inclinometer", "end-effector angle in the base plane (example)",
                       read_inclinometer, write_inclinometer});
  registry.add_preset({"two-link-demo",
                       "300 mm + 200 mm two-link arm, a length gauge and an inclinometer "
                       "(docs/extending.md)",
                       make_demo});
}

}  // namespace example
