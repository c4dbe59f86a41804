#pragma once
// `ipopt`: Ipopt's interior-point method on min 1/2 |r|^2 (no constraints, optional bounds),
// with the exact gradient J^T r and the Gauss-Newton Hessian J^T J (or Ipopt's limited-memory
// quasi-Newton). Options and status mapping: docs/solvers.md.

#include <memory>
#include <string>
#include <vector>

#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

/// ipopt's own settings (SolverOptions::backend), passed to Ipopt's options of those names.
struct IpoptSettings final : TypedBackendSettings<IpoptSettings> {
  std::string hessian = "gauss-newton";  ///< J^T J, or limited-memory (Ipopt's quasi-Newton)
  std::string mu_strategy = "monotone";  ///< or adaptive
  /// mumps (built into Debian's Ipopt); ma27, ma57, ma77, ma86, ma97, pardiso when their
  /// libraries load at run time (check_options says when they cannot)
  std::string linear_solver = "mumps";

  static const std::vector<SettingField<IpoptSettings>>& fields();
};

std::unique_ptr<Solver> make_ipopt_solver();

}  // namespace kincal
