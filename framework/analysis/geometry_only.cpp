#include "kincal/framework/analysis/geometry_only.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "kincal/framework/kinematics/units.hpp"

namespace kincal {

std::optional<GeometryOnlyEffect> geometry_only_effect(const MeasurementModel& model,
                                                       const VectorXd& values,
                                                       const Measurements& data) {
  const std::vector<int> indices = model.mechanism().non_geometric_parameters();
  bool any = false;
  for (int i : indices) any = any || values[i] != 0;
  if (!any) return std::nullopt;
  VectorXd geometry = values;
  for (int i : indices) geometry[i] = 0;
  const std::vector<std::string> units = model.reading_units();
  GeometryOnlyEffect effect;
  for (int i : indices) effect.parameters.push_back(model.parameters()[i].name);
  auto ws = model.make_workspace();
  VectorXd with(model.num_readings()), without(model.num_readings());
  for (int c = 0; c < data.size(); ++c) {
    const VectorXd q = data.actuators.row(c).transpose();
    if (!model.predict(values, q, with, nullptr, ws).ok()) continue;
    if (!model.predict(geometry, q, without, nullptr, ws).ok()) continue;
    double sum = 0;
    bool counted = false;
    for (int k = 0; k < model.num_readings(); ++k)
      if (units[static_cast<std::size_t>(k)] == kMillimetre && std::isfinite(with[k]) &&
          std::isfinite(without[k])) {
        sum += (with[k] - without[k]) * (with[k] - without[k]);
        counted = true;
      }
    if (!counted) continue;
    const double d = std::sqrt(sum);
    effect.mean += d;
    effect.max = std::max(effect.max, d);
    ++effect.configurations;
  }
  if (effect.configurations == 0) return std::nullopt;
  effect.mean /= effect.configurations;
  return effect;
}

std::string geometry_only_text(const GeometryOnlyEffect& effect) {
  char text[800];
  std::snprintf(text, sizeof text,
                "a kinematic export (URDF, DH) holds the geometry only: loading it alone leaves "
                "the joints' deflection under gravity uncorrected, %.4g %s mean / %.4g %s max at "
                "the %d measured configurations. The compliance stays in the model file (kincal "
                "compensate writes commands that include it); for a controller that loads only "
                "the geometry, calibrate without compliance: the geometry fitted with it is not "
                "the best one alone",
                effect.mean, effect.unit.c_str(), effect.max, effect.unit.c_str(),
                effect.configurations);
  return text;
}

nlohmann::ordered_json geometry_only_json(const GeometryOnlyEffect& effect) {
  return {{"configurations", effect.configurations},
          {"mean", effect.mean},
          {"max", effect.max},
          {"unit", effect.unit},
          {"parameters", effect.parameters},
          {"text", geometry_only_text(effect)}};
}

}  // namespace kincal
