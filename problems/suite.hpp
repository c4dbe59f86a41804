#pragma once
// The suite's starting points and what counts as reaching a published minimum.

#include <string>
#include <vector>

#include "kincal/problems/test_problem.hpp"

namespace kincal::problems {

/// One of a problem's standard starts: x0, 10 x0, 100 x0 (MGH's practice).
struct SuiteStart {
  std::string label;  ///< "x0", "10x0", "100x0"
  VectorXd x;
  bool evaluable = true;          ///< false when the residuals cannot be computed there
  std::string why_not_evaluable;  ///< the problem's reason, e.g. "... overflows"
};

/// The distinct starts of `problem` (a start that scales to itself, like Watson's origin, is
/// listed once). Starts whose cost overflows double precision are listed, not evaluable:
/// no backend can start there, so the suite reports them and leaves them out of its counts.
std::vector<SuiteStart> suite_starts(const TestProblem& problem);

/// Where a solve ended, judged by its cost against the published values.
enum class Outcome {
  kPublishedMinimum,  ///< the lowest published value, to 4 digits (see reaches())
  kPublishedLocal,    ///< one of the published local minima, to 4 digits
  kElsewhere,         ///< anything else
};
const char* to_string(Outcome outcome);

/// A published value is reached when cost <= value (1 + 1e-4), i.e. 4 digits, or, for a
/// value of 0, when cost <= kZeroCostTolerance.
constexpr double kRelativeCostTolerance = 1e-4;
constexpr double kZeroCostTolerance = 1e-10;
bool reaches(double cost, double published);
Outcome classify(const TestProblem& problem, double cost);

}  // namespace kincal::problems
