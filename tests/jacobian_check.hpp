#pragma once
// Central finite differences for checking analytic Jacobians (manif/GTSAM style): the
// helper reports the worst entry and its position so a failure names the block.

#include <gtest/gtest.h>

#include <functional>
#include <sstream>

#include "kincal/framework/types.hpp"

namespace kincal::testing {

/// Numerical Jacobian of f: R^n -> R^m at x by central differences with step h.
inline MatrixXd numerical_jacobian(const std::function<VectorXd(const VectorXd&)>& f,
                                   const VectorXd& x, double h) {
  const VectorXd f0 = f(x);
  MatrixXd J(f0.size(), x.size());
  for (int i = 0; i < x.size(); ++i) {
    VectorXd xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    J.col(i) = (f(xp) - f(xm)) / (2 * h);
  }
  return J;
}

/// Passes when |analytic - numeric| <= tol * (1 + |numeric|) entrywise.
inline ::testing::AssertionResult jacobians_match(const MatrixXd& analytic, const MatrixXd& numeric,
                                                  double tol,
                                                  const std::vector<std::string>& col_names = {}) {
  if (analytic.rows() != numeric.rows() || analytic.cols() != numeric.cols())
    return ::testing::AssertionFailure()
           << "size mismatch " << analytic.rows() << "x" << analytic.cols() << " vs "
           << numeric.rows() << "x" << numeric.cols();
  double worst = 0;
  int wr = 0, wc = 0;
  for (int r = 0; r < analytic.rows(); ++r)
    for (int c = 0; c < analytic.cols(); ++c) {
      const double e = std::abs(analytic(r, c) - numeric(r, c)) / (1 + std::abs(numeric(r, c)));
      if (e > worst) worst = e, wr = r, wc = c;
    }
  if (worst <= tol) return ::testing::AssertionSuccess();
  std::ostringstream os;
  os << "worst relative error " << worst << " at (" << wr << ", " << wc;
  if (wc < static_cast<int>(col_names.size())) os << " '" << col_names[wc] << "'";
  os << "): analytic " << analytic(wr, wc) << " vs numeric " << numeric(wr, wc);
  return ::testing::AssertionFailure() << os.str();
}

}  // namespace kincal::testing
