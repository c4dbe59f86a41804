#pragma once
// Finite-difference checks of analytic Jacobians in the tests: the library's own
// (models/conformance.hpp, what `kincal check` runs), as a gtest assertion that names the
// worst entry and its column.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "kincal/models/conformance.hpp"

namespace kincal::testing {

using kincal::numerical_jacobian;

/// Passes when |analytic - numeric| <= tol * (1 + |numeric|) entrywise (a NaN fails).
inline ::testing::AssertionResult jacobians_match(const MatrixXd& analytic, const MatrixXd& numeric,
                                                  double tol,
                                                  const std::vector<std::string>& col_names = {}) {
  const ConformanceCheck check = compare_jacobians("", analytic, numeric, tol, col_names);
  if (check.passed) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "worst relative error " << check.worst << ", " << check.detail;
}

}  // namespace kincal::testing
