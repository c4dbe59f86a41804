#pragma once
// `lm`: Levenberg-Marquardt on Eigen, the project's default solver. Trust-region damping
// with gain-ratio (Nielsen) radius updates, Marquardt diagonal scaling, Ceres' termination
// tests, optional box constraints (projected steps) and robust losses (Triggs/IRLS
// rescaling). Options and algorithm: docs/solvers.md.

#include <memory>

#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

std::unique_ptr<Solver> make_levenberg_marquardt_solver();

}  // namespace kincal
