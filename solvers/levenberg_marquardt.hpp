#pragma once
// `lm`: Levenberg-Marquardt on Eigen, the project's default solver. Trust-region damping
// with gain-ratio (Nielsen) radius updates, Marquardt diagonal scaling, Ceres' termination
// tests, optional box constraints (projected steps) and robust losses (Triggs/IRLS
// rescaling). Options and algorithm: docs/solvers.md.

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

/// lm's own settings (SolverOptions::backend; docs/solvers.md lists what each does). The
/// robust loss is SolverOptions::loss, shared with the other backends that take one.
struct LevenbergMarquardtSettings final : TypedBackendSettings<LevenbergMarquardtSettings> {
  std::string linear_solver = "cholesky";  ///< cholesky (normal equations) or qr
  double initial_trust_radius = 1e4;       ///< Ceres' default: starts close to Gauss-Newton
  double max_trust_radius = 1e16;
  double min_trust_radius = 1e-32;
  double min_relative_decrease = 1e-3;  ///< accept a step when its gain ratio exceeds this
  double max_radius_growth = 10;  ///< cap on the radius increase per step (Nielsen: 3; measured)
  int max_invalid_steps = 10;     ///< consecutive unusable trial points before giving up
  /// Off ("none"): a fixed distance from the start stopped legitimate solves (Brown badly
  /// scaled: the minimum lies 1e6 from the start); iterates that run off towards an asymptote
  /// are named by the plateau test instead.
  double runaway_factor = std::numeric_limits<double>::infinity();
  bool geodesic_acceleration = true;
  double geodesic_step = 0.1;      ///< h of the finite-difference second directional derivative
  double max_acceleration = 0.75;  ///< use only when 2|a| <= this * |v| (Transtrum's alpha)
  bool uphill_steps = true;
  double max_uphill_ratio = 2;  ///< an uphill step may cost at most this times the best cost

  static const std::vector<SettingField<LevenbergMarquardtSettings>>& fields();
  std::string validity_error() const override;
};

std::unique_ptr<Solver> make_levenberg_marquardt_solver();

}  // namespace kincal
