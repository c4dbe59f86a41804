// The stationarity measures behind the honesty contract, on cases whose answers are known.

#include <gtest/gtest.h>

#include <cmath>

#include "kincal/framework/least_squares/stationarity.hpp"

namespace kincal {
namespace {

SolverOptions defaults() { return SolverOptions{}; }

TEST(Stationarity, LinearResidualsAreMeasuredExactly) {
  // r = x - b with J = I: the gradient is r, and the model along it reaches b, promising the
  // whole cost (the Cauchy point; with both its tests failing, the Gauss-Newton step, which
  // could only promise more, is not computed).
  const Eigen::Vector2d x(1, 2), b(1.5, 2);
  const VectorXd r = x - b;
  const MatrixXd J = MatrixXd::Identity(2, 2);
  const Stationarity s = measure_stationarity(x, r, J, defaults());
  EXPECT_DOUBLE_EQ(s.cost, 0.125);
  EXPECT_DOUBLE_EQ(s.gradient_norm, 0.5);
  EXPECT_FALSE(s.gauss_newton_trusted);
  EXPECT_NEAR(s.predicted_relative_decrease, 1.0, 1e-15);
  EXPECT_NEAR(s.relative_step, 0.5 / (x.norm() + defaults().parameter_tolerance), 1e-15);
  EXPECT_FALSE(s.cost_test(defaults()));
  EXPECT_FALSE(s.gradient_test(defaults()));
  EXPECT_TRUE(s.dead_parameters.empty());
}

TEST(Stationarity, ANonZeroResidualMinimumPassesTheCostTest) {
  // Two residuals, one parameter: r = (x - 1, x + 1) has its minimum at x = 0, cost 1.
  const VectorXd x = VectorXd::Zero(1);
  const Eigen::Vector2d r(-1, 1);
  const MatrixXd J = MatrixXd::Ones(2, 1);
  const Stationarity s = measure_stationarity(x, r, J, defaults());
  EXPECT_EQ(s.gradient_norm, 0);
  EXPECT_EQ(s.predicted_relative_decrease, 0);
  EXPECT_TRUE(s.claim_holds(defaults(), true));
  EXPECT_TRUE(s.claim_holds(defaults(), false));
}

TEST(Stationarity, ALongGaussNewtonStepFallsBackToTheCauchyPoint) {
  // A nearly singular J with the residual along its weak direction, as at Freudenstein-Roth's
  // local minimum: Gauss-Newton jumps 1e6 |x| away and promises everything; along the
  // gradient, which the strong direction dominates, the model promises next to nothing.
  const Eigen::Vector2d x(1, 1);
  MatrixXd J(2, 2);
  J << 1, 0, 0, 1e-7;
  const Eigen::Vector2d r(5e-9, 1e-2);
  const Stationarity s = measure_stationarity(x, r, J, defaults());
  EXPECT_FALSE(s.gauss_newton_trusted);
  EXPECT_LT(s.predicted_relative_decrease, 1e-12);
  EXPECT_TRUE(s.cost_test(defaults()));
}

TEST(Stationarity, DeadColumnsAndPlateausAreRecognised) {
  // The second column vanished (an underflowed exponential), the first did not.
  const Eigen::Vector2d x(1, 500);
  MatrixXd J(2, 2);
  J << 1, 0, 0, 1e-300;
  const Eigen::Vector2d r(0, 3);
  const Stationarity partial = measure_stationarity(x, r, J, defaults());
  ASSERT_EQ(partial.dead_parameters, std::vector<int>{1});
  EXPECT_FALSE(partial.on_plateau());
  J.col(0).setZero();
  const Stationarity whole = measure_stationarity(x, r, J, defaults());
  EXPECT_TRUE(whole.on_plateau());
  EXPECT_FALSE(whole.claim_holds(defaults(), true)) << "a vanished gradient is no minimum";
}

TEST(Stationarity, ParametersHeldAtABoundAreLeftOut) {
  // The gradient pushes x0 below its lower bound 0, where it sits: the projected gradient is
  // 0 and the other parameter is at its minimum.
  const Eigen::Vector2d x(0, 2);
  const MatrixXd J = MatrixXd::Identity(2, 2);
  const Eigen::Vector2d r(0.5, 0);  // r = x - (-0.5, 2)
  SolverOptions options;
  options.lower_bounds = Eigen::Vector2d(0, -10);
  options.upper_bounds = Eigen::Vector2d(10, 10);
  const Stationarity s = measure_stationarity(x, r, J, options);
  EXPECT_EQ(s.gradient_norm, 0);
  EXPECT_TRUE(s.claim_holds(options, true));
  // Just inside the bound, as an interior-point iterate is: still held.
  const Eigen::Vector2d inside(1e-9, 2);
  EXPECT_TRUE(measure_stationarity(inside, Eigen::Vector2d(0.5 + 1e-9, 0), J, options)
                  .claim_holds(options, false));
}

TEST(Stationarity, TheCostRoundingFollowsTheSizeOfTheTerms) {
  // A residual that is the difference of two 600-unit terms is good to ~eps * 600, however
  // small it is: the cost's rounding scales with those terms, not with the residual alone.
  const VectorXd x = VectorXd::Constant(1, 600);
  const VectorXd r = VectorXd::Constant(1, 1e-3);
  const MatrixXd J = MatrixXd::Ones(1, 1);
  const double eps = std::numeric_limits<double>::epsilon();
  EXPECT_NEAR(cost_rounding(x, r, J), 1e-3 * eps * (600 + 1e-3), 1e-3 * eps);
  const Stationarity s = measure_stationarity(x, r, J, defaults());
  EXPECT_DOUBLE_EQ(s.cost_rounding, cost_rounding(x, r, J));
  EXPECT_GT(s.gradient_rounding, eps * 600);
}

// Multiplying every residual by one constant (a model's reading_std, a robust loss's delta)
// does not move the minimum, so it must not change a verdict. The gradient test compared
// max|J^T r| with an absolute 1e-12, which a factor of 1e-8 (the cost's 1e-16) passed at once
// (issue 35); it is now relative to |J_j| |r|.
TEST(Stationarity, TheVerdictsDoNotDependOnACommonScaleOfTheResiduals) {
  // Noisy, not yet at the minimum: a small step of a nonzero-residual problem remains.
  const Eigen::Vector3d x(1, 2, 3);
  MatrixXd J(4, 3);
  J << 1, 0.5, 0, 0, 1, 0.2, 0.3, 0, 1, 1, 1, 1;
  const Eigen::Vector4d r(1e-3, -2e-3, 1.5e-3, 0.3);
  const SolverOptions options;
  const Stationarity one = measure_stationarity(x, r, J, options);
  for (double scale : {1e-8, 0.0072, 1e8}) {
    SCOPED_TRACE(scale);
    const Stationarity scaled = measure_stationarity(x, scale * r, scale * J, options);
    EXPECT_EQ(scaled.gradient_test(options), one.gradient_test(options));
    EXPECT_EQ(scaled.cost_test(options), one.cost_test(options));
    EXPECT_EQ(scaled.step_test(options), one.step_test(options));
    EXPECT_EQ(scaled.claim_holds(options, true), one.claim_holds(options, true));
    EXPECT_EQ(scaled.claim_holds(options, false), one.claim_holds(options, false));
    EXPECT_EQ(scaled.dead_parameters, one.dead_parameters);
    EXPECT_NEAR(scaled.relative_gradient, one.relative_gradient, 1e-12);
    EXPECT_NEAR(scaled.predicted_relative_decrease, one.predicted_relative_decrease, 1e-12);
    EXPECT_NEAR(scaled.relative_step, one.relative_step, 1e-12 * one.relative_step);
    EXPECT_NEAR(scaled.gradient_norm, scale * scale * one.gradient_norm,
                1e-12 * scale * scale * one.gradient_norm);
  }
  EXPECT_FALSE(one.claim_holds(options, true));
  EXPECT_FALSE(one.claim_holds(options, false));
}

TEST(Stationarity, TheGradientTestIsTheCosineOfResidualsAndColumns) {
  // r = (1, 1) against the columns (1, 0) and (0, 1e-3): cosines 1/sqrt(2) each, however short
  // the second column; at the minimum of r = (1, -1) with J = (1, 1)^T, 0.
  const Eigen::Vector2d x(0, 0);
  MatrixXd J(2, 2);
  J << 1, 0, 0, 1e-3;
  const Stationarity s = measure_stationarity(x, Eigen::Vector2d(1, 1), J, SolverOptions{});
  EXPECT_NEAR(s.raw_relative_gradient, std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(relative_gradient(x, Eigen::Vector2d(1, 1), J, SolverOptions{}), std::sqrt(0.5),
              1e-15);
  const Stationarity minimum = measure_stationarity(VectorXd::Zero(1), Eigen::Vector2d(1, -1),
                                                    MatrixXd::Ones(2, 1), SolverOptions{});
  EXPECT_EQ(minimum.raw_relative_gradient, 0);
  EXPECT_TRUE(minimum.gradient_test(SolverOptions{}));
}

// A NaN compares false with every tolerance and max(0, NaN) is 0: a NaN Jacobian once passed
// the gradient test (ipopt and nlopt:LD_LBFGS called such a start `converged`, issue 35).
TEST(Stationarity, ANonFiniteJacobianPassesNoTest) {
  const Eigen::Vector2d x(1, 2);
  MatrixXd J = MatrixXd::Identity(2, 2);
  J(1, 0) = std::nan("");
  const Eigen::Vector2d r(0.5, 0.25);
  const SolverOptions options;
  const Stationarity s = measure_stationarity(x, r, J, options);
  EXPECT_FALSE(s.finite);
  EXPECT_FALSE(s.gradient_test(options));
  EXPECT_FALSE(s.claim_holds(options, true));
  EXPECT_FALSE(s.claim_holds(options, false));
  EXPECT_FALSE(s.on_plateau());
  J(1, 0) = HUGE_VAL;
  EXPECT_FALSE(measure_stationarity(x, r, J, options).claim_holds(options, false));
  EXPECT_FALSE(
      measure_stationarity(x, Eigen::Vector2d(std::nan(""), 0), MatrixXd::Identity(2, 2), options)
          .claim_holds(options, false));
}

TEST(Stationarity, DescribesParametersByName) {
  EXPECT_EQ(describe_parameters({0, 3}), "x0, x3");
  EXPECT_EQ(describe_parameters({1}, {"a", "b"}), "b");
}

}  // namespace
}  // namespace kincal
