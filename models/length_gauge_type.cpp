// The length gauge in model files:
//   { "type": "length-gauge", "name": "gauge", "base": [x, y, z], "platform": [x, y, z],
//     "offset": 0 }

#include "kincal/framework/model_registry.hpp"
#include "kincal/models/length_gauge.hpp"

namespace kincal {

namespace {

using namespace json_field;

std::shared_ptr<const Sensor> read_gauge(const Json& j, const JsonPath& where) {
  check_keys(j, where, {"type", "name", "base", "platform", "offset"});
  const std::string gauge_name = name(member(j, "name", where), where / "name");
  return std::make_shared<LengthGauge>(gauge_name,
                                       vector3(member(j, "base", where), where / "base"),
                                       vector3(member(j, "platform", where), where / "platform"),
                                       number_or(j, "offset", 0.0, where));
}

Json write_gauge(const Sensor& sensor, const Eigen::Ref<const VectorXd>& values) {
  return {{"name", sensor.name()},
          {"base", array3(values.segment<3>(LengthGauge::kBaseIndex))},
          {"platform", array3(values.segment<3>(LengthGauge::kPlatformIndex))},
          {"offset", values[LengthGauge::kOffsetIndex]}};
}

}  // namespace

void register_length_gauge(ModelRegistry& registry) {
  registry.add_sensor({"length-gauge",
                       "distance between a base point and a platform point (draw-wire encoder, "
                       "ball-bar); one reading in mm",
                       read_gauge, write_gauge});
}

}  // namespace kincal
