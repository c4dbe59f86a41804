#pragma once
// `gn`: the paper's undamped Gauss-Newton (eq. 26), each step solved by column-pivoting QR
// of J rather than by inverting J^T J. No bounds: check_options rejects them.

#include <memory>

#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

std::unique_ptr<Solver> make_gauss_newton_solver();

}  // namespace kincal
