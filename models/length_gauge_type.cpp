// The length gauge in model files (framework/extension/generic_model_file.hpp, from its
// parameters):
//   { "type": "length-gauge", "name": "gauge", "base": [x, y, z], "platform": [x, y, z],
//     "offset": 0 }

#include "kincal/framework/extension/generic_model_file.hpp"
#include "kincal/models/length_gauge.hpp"

namespace kincal {

void register_length_gauge(ModelRegistry& registry) {
  const LengthGauge prototype("gauge", Vector3d::Zero(), Vector3d::Zero());
  registry.add_sensor(generic_sensor_type(
      "length-gauge",
      "distance between a base point and a platform point (draw-wire encoder, ball-bar); one "
      "reading in mm",
      sensor_layout(prototype, {"offset"}),
      [](const std::string& name, const VectorXd& v, const ModelFileOptions&) {
        return std::make_shared<LengthGauge>(name, v.segment<3>(LengthGauge::kBaseIndex),
                                             v.segment<3>(LengthGauge::kPlatformIndex),
                                             v[LengthGauge::kOffsetIndex]);
      }));
}

}  // namespace kincal
