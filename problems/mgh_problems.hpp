#pragma once
// The Moré-Garbow-Hillstrom collection as kincal's standard solver test suite: all 35
// unconstrained least-squares problems of ACM TOMS 7(1), 1981, each a LeastSquaresProblem
// with an analytic Jacobian, its standard start and the published minima (as 1/2 |r|^2).
// The variable-size problems come at the sizes for which the paper publishes a minimum
// (docs/solvers.md lists them); a few at more than one size.

#include <memory>
#include <string>
#include <vector>

#include "kincal/problems/test_problem.hpp"

namespace kincal::problems {

/// Every suite problem, in the paper's order (built once; shared and immutable).
const std::vector<std::shared_ptr<const TestProblem>>& mgh_problems();

/// The suite problems whose name matches `pattern`: a glob with '*' and '?', or, without
/// wildcards, any name that contains it ("watson" selects the three Watson sizes). Throws
/// std::invalid_argument naming the pattern when nothing matches.
std::vector<std::shared_ptr<const TestProblem>> select_problems(const std::string& pattern);

}  // namespace kincal::problems
