#pragma once
// How stationary a point is, measured at that point alone from r(x) and J(x): what a
// `converged` claim must be true of (docs/solvers.md, "The honesty contract"). Backends use it
// to check their own claims before making them; the contract checker
// (problems/solver_contract.hpp) recomputes it at the point a backend returned.

#include <algorithm>
#include <string>
#include <vector>

#include "kincal/framework/base/triangular_factor.hpp"
#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

struct Stationarity {
  double cost = 0;  ///< 1/2 |r|^2
  /// max |P(g)|, g = J^T r, projected onto the box when bounds are given (Ceres' test).
  double gradient_norm = 0;
  /// The rounding error of the computed cost, estimated (see cost_rounding()): two costs
  /// closer than this cannot be told apart, and a decrease smaller than this cannot be
  /// verified by any step.
  double cost_rounding = 0;
  /// The rounding error of the entries of the computed gradient, from the same estimate of the
  /// residuals' error plus the dot product's own: gradient tests pass when
  /// gradient_norm <= tolerance + gradient_rounding.
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

  /// Whether a convergence claim holds here: a gradient claim needs the gradient test itself,
  /// any other claim one of the three tests; never on a plateau.
  bool claim_holds(const SolverOptions& options, bool gradient_claim) const {
    if (on_plateau()) return false;
    return gradient_claim ? gradient_test(options)
                          : gradient_test(options) || cost_test(options) || step_test(options);
  }
  bool gradient_test(const SolverOptions& options) const {
    return gradient_norm <= options.gradient_tolerance + gradient_rounding;
  }
  bool cost_test(const SolverOptions& options) const {
    return predicted_relative_decrease * cost <= options.function_tolerance * cost + cost_rounding;
  }
  bool step_test(const SolverOptions& options) const {
    return relative_step <= options.parameter_tolerance;
  }
  /// Every free parameter is dead while the cost is not zero: no derivative information at all.
  bool on_plateau() const {
    return cost > 0 && num_free > 0 && static_cast<int>(dead_parameters.size()) >= num_free;
  }
};

constexpr double kDeadColumnRatio = 1e-6;
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
