#pragma once
// `nlopt:<ALGORITHM>`: any NLopt algorithm minimising 1/2 |r|^2, with the exact gradient
// J^T r for the derivative-based ones. Options and result-code mapping: docs/solvers.md.

#include <memory>
#include <string>
#include <vector>

#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

/// The settings of every nlopt:<ALGORITHM> (SolverOptions::backend; docs/solvers.md).
struct NloptSettings final : TypedBackendSettings<NloptSettings> {
  /// The first step of derivative-free algorithms, the same for every parameter; 0: NLopt's
  /// own choice.
  double initial_step = 0;
  /// The subsidiary optimiser of AUGLAG and MLSL (an LD_* or LN_* name); empty: the
  /// algorithm's default (LD_LBFGS where one is required).
  std::string local_algorithm;
  /// Global algorithms without bounds search x0 +- this.
  double box_half_width = 10;
  int seed = 1;                      ///< NLopt's random seed (stochastic algorithms)
  std::string scaling = "jacobian";  ///< or none: variables scaled by the Jacobian's columns

  static const std::vector<SettingField<NloptSettings>>& fields();
  std::string validity_error() const override;
};

/// `algorithm` is an NLopt name such as "LD_LBFGS". Throws InvalidSolverOptions listing the
/// valid names when it is not one, and saying so when this NLopt library cannot run it
/// (LD_LBFGS_NOCEDAL, which NLopt lists but never ships).
std::unique_ptr<Solver> make_nlopt_solver(const std::string& algorithm);

/// The algorithms worth testing and benchmarking on our problems.
std::vector<std::string> nlopt_featured_algorithms();

}  // namespace kincal
