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

TEST(Stationarity, DescribesParametersByName) {
  EXPECT_EQ(describe_parameters({0, 3}), "x0, x3");
  EXPECT_EQ(describe_parameters({1}, {"a", "b"}), "b");
}

}  // namespace
}  // namespace kincal
