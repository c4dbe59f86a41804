#pragma once
// `gn`: the paper's undamped Gauss-Newton (eq. 26), each step solved by column-pivoting QR
// of J rather than by inverting J^T J. No bounds: check_options rejects them.

#include <memory>
#include <string>
#include <vector>

#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

/// gn's own settings (SolverOptions::backend).
struct GaussNewtonSettings final : TypedBackendSettings<GaussNewtonSettings> {
  /// Diverged when the parameters move further than this times (1 + max|x0|) from the start.
  double runaway_factor = 1e3;

  static const std::vector<SettingField<GaussNewtonSettings>>& fields();
  std::string validity_error() const override;
};

std::unique_ptr<Solver> make_gauss_newton_solver();

}  // namespace kincal
