#pragma once
// `ceres`: Ceres Solver with one residual block per measured configuration and the analytic
// Jacobian of the problem. No Ceres header here: only solvers/ceres_solver.cpp sees Ceres.

#include <memory>

#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

std::unique_ptr<Solver> make_ceres_solver();

}  // namespace kincal
