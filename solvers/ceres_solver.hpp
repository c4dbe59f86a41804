#pragma once
// `ceres`: Ceres Solver with one residual block per measured configuration and the analytic
// Jacobian of the problem. No Ceres header here: only solvers/ceres_solver.cpp sees Ceres.

#include <memory>
#include <string>
#include <vector>

#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

/// ceres' own settings (SolverOptions::backend), passed to ceres::Solver::Options; the robust
/// loss is SolverOptions::loss.
struct CeresSettings final : TypedBackendSettings<CeresSettings> {
  std::string trust_region = "levenberg_marquardt";  ///< or dogleg
  std::string dogleg_type = "traditional";           ///< or subspace (with dogleg)
  /// dense_qr, dense_normal_cholesky, dense_schur, sparse_normal_cholesky, cgnr,
  /// iterative_schur
  std::string linear_solver = "dense_qr";
  double initial_trust_region_radius = 1e4;  ///< Ceres' default

  static const std::vector<SettingField<CeresSettings>>& fields();
};

std::unique_ptr<Solver> make_ceres_solver();

}  // namespace kincal
