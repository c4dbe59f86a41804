// A plug-in that registers a solver backend: "plugin-gn", Gauss-Newton under another name
// (the plug-in's own copy of kincal's), so that a test can see a plug-in's backend used.

#include <kincal/framework/extension/plugin.hpp>

namespace {
void register_solver(kincal::ModelRegistry&, kincal::SolverRegistry& solvers) {
  solvers.add("plugin-gn", "Gauss-Newton from a plug-in (test)", kincal::SolverKind::kLeastSquares,
              [](const std::string&) { return kincal::SolverRegistry::global().create("gn"); });
}
}  // namespace

KINCAL_PLUGIN(register_solver)
