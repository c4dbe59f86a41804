// The one place that knows which backends are built: one registration line per backend.

#include "framework/solver_registry.hpp"
#include "solvers/gauss_newton.hpp"

namespace kincal {

void register_builtin_solvers(SolverRegistry& registry) {
  registry.add("gn", "Gauss-Newton as in the paper (undamped, QR-solved steps)",
               [](const std::string&) { return make_gauss_newton_solver(); });
}

}  // namespace kincal
