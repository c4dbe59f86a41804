// The one place that knows which backends are built: one registration line per backend.
// Optional backends are compiled in when their CMake option (KINCAL_WITH_<NAME>) is ON; when
// it is OFF they are registered as unavailable, so that `--solver ceres` says how to get it
// and the tests skip them with that reason.

#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/solvers/gauss_newton.hpp"
#include "kincal/solvers/levenberg_marquardt.hpp"
#ifdef KINCAL_WITH_CERES
#include "kincal/solvers/ceres_solver.hpp"
#endif
#ifdef KINCAL_WITH_NLOPT
#include "kincal/solvers/nlopt_solver.hpp"
#endif
#ifdef KINCAL_WITH_IPOPT
#include "kincal/solvers/ipopt_solver.hpp"
#endif

namespace kincal {

void register_builtin_solvers(SolverRegistry& registry) {
  using K = SolverKind;
  registry.add("gn", "Gauss-Newton as in the paper (undamped, QR-solved steps)", K::kLeastSquares,
               [](const std::string&) { return make_gauss_newton_solver(); });
  registry.add(
      "lm", "Levenberg-Marquardt on Eigen (default): trust-region damping, Marquardt scaling",
      K::kLeastSquares, [](const std::string&) { return make_levenberg_marquardt_solver(); });
#ifdef KINCAL_WITH_CERES
  registry.add("ceres", "Ceres Solver, trust region (LM, dense QR by default)", K::kLeastSquares,
               [](const std::string&) { return make_ceres_solver(); });
#else
  registry.add_unavailable("ceres", K::kLeastSquares,
                           "built with KINCAL_WITH_CERES=OFF (reconfigure with it ON)");
#endif
#ifdef KINCAL_WITH_NLOPT
  registry.add_family(
      "nlopt", "NLopt minimising the sum of squares (any NLopt algorithm name)",
      K::kGeneralMinimizer,
      [](const std::string& algorithm) { return make_nlopt_solver(algorithm); },
      nlopt_featured_algorithms());
#else
  registry.add_unavailable("nlopt", K::kGeneralMinimizer,
                           "built with KINCAL_WITH_NLOPT=OFF (reconfigure with it ON)");
#endif
#ifdef KINCAL_WITH_IPOPT
  registry.add("ipopt", "Ipopt interior point with the Gauss-Newton Hessian J^T J",
               K::kLeastSquares, [](const std::string&) { return make_ipopt_solver(); });
#else
  registry.add_unavailable("ipopt", K::kLeastSquares,
                           "built with KINCAL_WITH_IPOPT=OFF (reconfigure with it ON)");
#endif
}

}  // namespace kincal
