// A plug-in as one built against another kincal would look to the loader: the entry point
// by hand, with another version string. Loading it must be refused before its registration
// function runs (which would abort the test).

#include <cstdlib>
#include <kincal/framework/extension/plugin.hpp>

namespace {
void register_nothing(kincal::ModelRegistry&, kincal::SolverRegistry&) { std::abort(); }
}  // namespace

extern "C" __attribute__((visibility("default"))) const kincal_plugin_info* kincal_plugin_entry() {
  static const kincal_plugin_info info = {KINCAL_PLUGIN_MAGIC, KINCAL_PLUGIN_INFO_LAYOUT,
                                          "0.0.0-elsewhere", KINCAL_PLUGIN_ABI_TAG,
                                          &register_nothing};
  return &info;
}
