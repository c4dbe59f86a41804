#pragma once
// `nlopt:<ALGORITHM>`: any NLopt algorithm minimising 1/2 |r|^2, with the exact gradient
// J^T r for the derivative-based ones. Options and result-code mapping: docs/solvers.md.

#include <memory>
#include <string>
#include <vector>

#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

/// `algorithm` is an NLopt name such as "LD_LBFGS". Throws InvalidSolverOptions listing the
/// valid names when it is not one, and saying so when this NLopt library cannot run it
/// (LD_LBFGS_NOCEDAL, which NLopt lists but never ships).
std::unique_ptr<Solver> make_nlopt_solver(const std::string& algorithm);

/// The algorithms worth testing and benchmarking on our problems.
std::vector<std::string> nlopt_featured_algorithms();

}  // namespace kincal
