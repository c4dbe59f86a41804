// A plug-in whose preset takes a built-in name: loading it must fail naming both.

#include <kincal/framework/extension/plugin.hpp>
#include <stdexcept>

namespace {
void register_clash(kincal::ModelRegistry& models, kincal::SolverRegistry&) {
  models.add_preset(
      {"puma560", "a second puma560 (test)", []() -> std::shared_ptr<kincal::MeasurementModel> {
         throw std::logic_error("never made");
       }});
}
}  // namespace

KINCAL_PLUGIN(register_clash)
