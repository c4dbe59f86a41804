#pragma once
// Robust losses for data with outliers, written as the backend option
//   loss=none | huber:<delta> | cauchy:<delta>      (delta in residual units, mm)
// With s = r^2 the cost of a residual is 1/2 rho(s) instead of 1/2 s:
//   huber:  rho(s) = s                          for s <= delta^2
//                    2 delta sqrt(s) - delta^2  otherwise
//   cauchy: rho(s) = delta^2 log(1 + s / delta^2)

#include <array>
#include <string>

#include "kincal/framework/base/types.hpp"

namespace kincal {

struct RobustLoss {
  enum class Kind { kNone, kHuber, kCauchy };
  Kind kind = Kind::kNone;
  double delta = 1.0;

  /// Throws std::invalid_argument for anything but the forms above (delta > 0).
  static RobustLoss parse(const std::string& text);
  std::string to_string() const;

  /// {rho(s), rho'(s), rho''(s)} at s = r^2 >= 0.
  std::array<double, 3> evaluate(double s) const;

  /// 1/2 sum rho(r_i^2): the robustified cost (1/2 |r|^2 without a loss).
  double cost(const VectorXd& r) const;

  /// Ceres' Corrector, per scalar residual (Triggs et al., Bundle adjustment - a modern
  /// synthesis, 4.3): rescales r and its Jacobian row so that the plain Gauss-Newton model of
  /// the rescaled problem matches the robust cost to second order, and J~^T r~ is the robust
  /// cost's gradient. Where rho'' <= 0 (Huber, Cauchy: always) this is IRLS, sqrt(rho').
  /// `row_scale` gets each row's Jacobian factor. Without a loss, nothing changes (ones).
  void correct(VectorXd& r, MatrixXd& J, VectorXd& row_scale) const;
};

}  // namespace kincal
