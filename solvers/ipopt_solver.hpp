#pragma once
// `ipopt`: Ipopt's interior-point method on min 1/2 |r|^2 (no constraints, optional bounds),
// with the exact gradient J^T r and the Gauss-Newton Hessian J^T J (or Ipopt's limited-memory
// quasi-Newton). Options and status mapping: docs/solvers.md.

#include <memory>

#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

std::unique_ptr<Solver> make_ipopt_solver();

}  // namespace kincal
