#include "kincal/models/presets.hpp"

#include <stdexcept>

#include "kincal/framework/extension/model_registry.hpp"

namespace kincal {

std::vector<PresetInfo> list_presets() {
  std::vector<PresetInfo> out;
  for (const auto& p : ModelRegistry::global().presets()) out.push_back({p.name, p.description});
  return out;
}

std::shared_ptr<MeasurementModel> make_preset(const std::string& name) {
  return ModelRegistry::global().make_preset(name);
}

}  // namespace kincal
