#pragma once
// How stationary a point is, measured at that point alone from r(x) and J(x): what a
// `converged` claim must be true of (docs/solvers.md, "The honesty contract"). Backends use it
// to check their own claims before making them; the contract checker
// (problems/solver_contract.hpp) recomputes it at the point a backend returned.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "kincal/framework/base/triangular_factor.hpp"
#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

struct Stationarity {
  double cost = 0;  ///< 1/2 |r|^2
  /// max |P(g)|, g = J^T r, projected onto the box when bounds are given (Ceres' quantity).
  /// For reports only: it scales with the square of the residuals' unit, so no test uses it.
  double gradient_norm = 0;
  /// The gradient test's measure: max_j over the live parameters of
  /// max(0, |P(g)_j| - rounding_j) / (|J_j| |r|), the cosine of the angle between the
  /// residuals and the parameter's Jacobian column (MINPACK's gtol), less the gradient's
  /// rounding error. Unlike max |J^T r| it does not change when every residual is multiplied
  /// by the same constant (a model's reading_std, a robust loss's delta), which does not move
  /// the minimum either; nor with the parameters' units. P projects onto the box in the
  /// Gauss-Newton metric (see relative_gradient_entry()).
  double relative_gradient = 0;
  /// The same before the rounding error is discounted (see relative_gradient() below).
  double raw_relative_gradient = 0;
  /// The rounding error of the computed cost, estimated (see cost_rounding()): two costs
  /// closer than this cannot be told apart, and a decrease smaller than this cannot be
  /// verified by any step.
  double cost_rounding = 0;
  /// The largest rounding error of an entry of the computed gradient, from the same estimate
  /// of the residuals' error plus the dot product's own (relative_gradient discounts each
  /// entry's own).
  double gradient_rounding = 0;
  /// The relative decrease of the cost that the Gauss-Newton model 1/2 |r + J dx|^2 promises,
  /// over the free, live parameters: at its minimum (the Gauss-Newton step dx = -J^+ r) when
  /// that step is no longer than the point itself (|dx| <= |x| + 1); otherwise at its minimum
  /// along the steepest-descent direction (the Cauchy point, |g|^4 / (2 |J g|^2 cost)). A
  /// longer step means the linearisation says nothing, as at any minimum of a non-zero-residual
  /// problem whose Jacobian is singular there (Freudenstein-Roth's local minimum: a Gauss-Newton
  /// step 1e7 times |x|), while the Cauchy decrease alone understates what is left by up to
  /// cond(J^T J) in a narrow valley.
  double predicted_relative_decrease = 0;
  /// The length of the same step (Gauss-Newton or Cauchy), relative as Ceres' step test:
  /// |dx| / (|x| + parameter_tolerance).
  double relative_step = 0;
  /// Which of the two the fields above give. When both Cauchy tests fail the Gauss-Newton
  /// step is not computed (it promises at least as much, and is at least as long), and the
  /// Cauchy values are reported.
  bool gauss_newton_trusted = false;
  /// Parameters whose Jacobian column is negligible here: changing the parameter by its own
  /// size (or by 1 near zero) changes the residuals by less than kDeadColumnRatio |r|.
  /// A gradient that vanishes in those directions says nothing about a minimum: the model
  /// saturated (an exponential underflowed, a parameter ran off to an asymptote) or the
  /// residuals do not depend on the parameter at all.
  std::vector<int> dead_parameters;
  int num_free = 0;  ///< parameters not held at a bound
  /// Whether every residual and Jacobian entry is finite. When not, nothing is measured (the
  /// tests all fail): a NaN compares false with every tolerance, and max(0, NaN) is 0, which
  /// once made a NaN gradient pass the gradient test (issue 35).
  bool finite = true;

  /// Whether a convergence claim holds here: a gradient claim needs the gradient test itself,
  /// any other claim one of the three tests; never on a plateau.
  bool claim_holds(const SolverOptions& options, bool gradient_claim) const {
    if (!finite || on_plateau()) return false;
    return gradient_claim ? gradient_test(options)
                          : gradient_test(options) || cost_test(options) || step_test(options);
  }
  bool gradient_test(const SolverOptions& options) const {
    return finite && relative_gradient <= options.gradient_tolerance;
  }
  bool cost_test(const SolverOptions& options) const {
    return finite &&
           predicted_relative_decrease * cost <= options.function_tolerance * cost + cost_rounding;
  }
  bool step_test(const SolverOptions& options) const {
    return finite && relative_step <= options.parameter_tolerance;
  }
  /// The three tests without their rounding allowances: what a backend stops on while it can
  /// still make progress (lm, the Ipopt backend), a claim then being judged by claim_holds().
  /// Near a noisy minimum the cost test holds with its allowance while the Gauss-Newton step
  /// still moves the parameters by ~1e-5 mm; without it, at the Gauss-Newton point itself.
  bool settled(const SolverOptions& options) const {
    return finite && !on_plateau() &&
           (raw_relative_gradient <= options.gradient_tolerance ||
            predicted_relative_decrease <= options.function_tolerance ||
            relative_step <= options.parameter_tolerance);
  }
  /// Every free parameter is dead while the cost is not zero: no derivative information at all.
  bool on_plateau() const {
    return finite && cost > 0 && num_free > 0 &&
           static_cast<int>(dead_parameters.size()) >= num_free;
  }
};

constexpr double kDeadColumnRatio = 1e-6;

/// One parameter's entry of the gradient test (Stationarity::relative_gradient) before the
/// rounding error is discounted: |P(g)_j| / (|J_j| |r|), with g_j = J_j^T r, `column_norm` =
/// |J_j| and `residual_norm` = |r|; 0 when J_j or r vanishes (g_j does too). With a box,
/// P(g)_j = |J_j|^2 (x_j - clamp(x_j - g_j / |J_j|^2)): the step the Gauss-Newton model takes
/// along this parameter alone, cut at the bound, in gradient units. That is Ceres' projected
/// gradient with the step measured in the model's metric instead of in the gradient's units,
/// which would compare millimetres squared with millimetres.
/// `lower`, `upper`: the parameter's bounds (infinite without a box).
inline double relative_gradient_entry(double g, double column_norm, double residual_norm, double x,
                                      double lower = -HUGE_VAL, double upper = HUGE_VAL) {
  if (!(column_norm > 0) || !(residual_norm > 0)) return 0;
  // Cut at the bound only when the step crosses it: x - clamp(x - step) would round a step
  // far smaller than x to nothing.
  double projected = g;
  const double curvature = column_norm * column_norm;
  const double target = x - g / curvature;
  if (target < lower) projected = curvature * (x - lower);
  if (target > upper) projected = curvature * (x - upper);
  return std::abs(projected) / column_norm / residual_norm;  // the product may overflow
}

/// Whether a parameter's Jacobian column is negligible at x: changing the parameter by its own
/// size (or by 1 near zero) changes the residuals by less than kDeadColumnRatio |r|. Relative
/// to |r|, so that a common scale of the residuals does not change the verdict.
inline bool dead_column(double column_norm, double x, double residual_norm) {
  return residual_norm > 0 && (column_norm == 0 || column_norm * std::max(std::abs(x), 1.0) <=
                                                       kDeadColumnRatio * residual_norm);
}
/// A parameter within this relative distance of a bound its gradient pushes against is held
/// there: left out of the Gauss-Newton and Cauchy steps (the projected gradient covers it).
constexpr double kBoundTolerance = 1e-6;

/// An estimate of the rounding error of the cost 1/2 |r|^2 at x: each residual is taken to be
/// good to eps (|r_i| + sum_j |J_ij x_j|), the size of the terms whose difference it is as the
/// linearisation sees them (a residual that is a difference of two 600 mm lengths is good to
/// ~1e-13 mm however small it is), giving sum_i |r_i| e_i + 1/2 sum_i e_i^2. On the noisy
/// hexapod cases this is 1e-9 - 1e-8 of the cost, about ten times the spread measured between
/// evaluations that differ by a few ulps; on the test suite's formulas, ~1e-15.
double cost_rounding(const VectorXd& x, const VectorXd& r, const MatrixXd& J);

/// The gradient test's measure before the rounding error is discounted: max over the live
/// parameters of relative_gradient_entry(), the box of `options` projecting. A backend stops on
/// it (<= gradient_tolerance), and its claim is then judged by Stationarity::gradient_test,
/// which also passes where the gradient is lost in its rounding error: stopping there would
/// leave work undone where rounding is loose (the noise-free hexapod: ~5e-5 mm). Infinite
/// when r or J has a non-finite entry.
double relative_gradient(const VectorXd& x, const VectorXd& r, const MatrixXd& J,
                         const SolverOptions& options);

/// Measures at x, with r = r(x) and J = J(x); the bounds of `options` decide the projection.
Stationarity measure_stationarity(const VectorXd& x, const VectorXd& r, const MatrixXd& J,
                                  const SolverOptions& options);

/// Working space of the measure, sized once with the problem's m and n: about n^2 + 1024 n
/// numbers besides two m-vectors, however large m. Nothing is allocated while the free
/// columns are clearly of full rank (near a rank deficiency the Gauss-Newton step's
/// decomposition still allocates).
struct StationarityScratch {
  StationarityScratch(int m, int n)
      : gradient(n),
        free_gradient(n),
        image(m),
        step(n),
        block(std::clamp(m, 1, kRowsPerBlock), n + 1),
        factor(n + 1, block.rows()) {
    free.reserve(static_cast<std::size_t>(n));
  }
  static constexpr int kRowsPerBlock = 1024;
  VectorXd gradient, free_gradient, image, step;
  MatrixXd block;           ///< rows of [scaled free columns of J, r, zeros]
  TriangularFactor factor;  ///< of those rows
  std::vector<int> free;
};

/// The same into `out`, reusing its dead_parameters' capacity.
void measure_stationarity(const VectorXd& x, const VectorXd& r, const MatrixXd& J,
                          const SolverOptions& options, StationarityScratch& scratch,
                          Stationarity& out);

/// "x3, x7" (1-based names as the paper writes them, or `names` when given).
std::string describe_parameters(const std::vector<int>& indices,
                                const std::vector<std::string>& names = {});

}  // namespace kincal
