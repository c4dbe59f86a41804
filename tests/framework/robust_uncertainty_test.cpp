// Standard deviations of a robust-loss (M-estimator) calibration: Huber's covariance on toy
// Jacobians where it can be written down, and against the real scatter of the estimates
// when the data has gross outliers.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "kincal/framework/analysis/calibration_report.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/framework/least_squares/uncertainty.hpp"
#include "kincal/models/presets.hpp"

namespace kincal {
namespace {

// The mean of m readings: J = ones, so (J^T J)^-1 = 1 / m.
MatrixXd mean_jacobian(int m) { return MatrixXd::Ones(m, 1); }

TEST(RobustUncertainty, WithoutOutliersHuberIsOrdinaryLeastSquares) {
  VectorXd r(6);
  r << 0.01, -0.02, 0.015, -0.005, 0.0, 0.01;
  const ParameterUncertainty plain = estimate_uncertainty(mean_jacobian(6), r);
  const ParameterUncertainty huber =
      estimate_uncertainty(mean_jacobian(6), r, RobustLoss::parse("huber:0.05"));
  EXPECT_EQ(plain.robust_factor, 1.0);
  EXPECT_EQ(huber.robust_factor, 1.0);  // every residual inside delta: psi' = 1
  EXPECT_DOUBLE_EQ(huber.sigma, plain.sigma);
  EXPECT_DOUBLE_EQ(huber.std[0], plain.std[0]);
  EXPECT_DOUBLE_EQ(plain.sigma, std::sqrt(r.squaredNorm() / 5));
}

TEST(RobustUncertainty, HuberFollowsHubersFormula) {
  // Five inliers and one outlier of 3 mm with delta 0.1: psi = delta there, psi' = 0.
  VectorXd r(6);
  r << 0.01, -0.02, 0.015, -0.005, 0.0, 3.0;
  const double delta = 0.1;
  const ParameterUncertainty u =
      estimate_uncertainty(mean_jacobian(6), r, RobustLoss::parse("huber:0.1"));
  const double sum_psi2 = r.head(5).squaredNorm() + delta * delta;
  EXPECT_NEAR(u.sigma, std::sqrt(sum_psi2 / 5), 1e-15);
  // psi' = (1, 1, 1, 1, 1, 0): mean 5/6, sample variance (5/6)(1/6) * 6/5 = 1/6.
  const double mean = 5.0 / 6, variance = 1.0 / 6;
  const double kappa = 1 + (1.0 / 6) * variance / (mean * mean);
  EXPECT_NEAR(u.robust_factor, kappa / mean, 1e-15);
  EXPECT_NEAR(u.std[0], kappa / mean * u.sigma / std::sqrt(6.0), 1e-15);
  // The outlier adds delta^2 to the noise estimate, not its 9 mm^2.
  EXPECT_LT(u.sigma, 0.06);
}

TEST(RobustUncertainty, DeltaTooSmallGivesNoStdRatherThanAWrongOne) {
  // Cauchy with delta far below every residual: psi' < 0 almost everywhere.
  VectorXd r(6);
  r << 1, -1, 2, -2, 1.5, -1.5;
  const ParameterUncertainty u =
      estimate_uncertainty(mean_jacobian(6), r, RobustLoss::parse("cauchy:0.01"));
  EXPECT_TRUE(std::isnan(u.robust_factor));
  EXPECT_TRUE(std::isnan(u.std[0]));
}

// 1.4826 * median absolute deviation: the standard deviation of the bulk of the estimates,
// not inflated by the few trials an outlier on a high-leverage configuration throws far.
double robust_spread(const VectorXd& values) {
  std::vector<double> v(values.data(), values.data() + values.size());
  const auto mid = v.begin() + static_cast<long>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  const double median = *mid;
  for (double& x : v) x = std::abs(x - median);
  std::nth_element(v.begin(), mid, v.end());
  return 1.4826 * *mid;
}

// Same truth and configurations, fresh noise and three gross outliers (50-150 times the
// noise, random configurations and signs) per trial: the reported std must describe the
// scatter of the robust estimates. Before the loss was taken into account the report was
// ~50 times too large here; the IRLS-weighted sigma^2 (J^T W J)^-1 was ~15 % too small.
void expect_std_matches_scatter(const std::string& loss_name) {
  ScenarioOptions options;
  options.num_configurations = 60;
  options.noise_half_width.set(kincal::kMillimetre, 0.0);
  options.num_validation = 0;
  options.seed = 11;
  const Scenario exact = make_scenario(make_cube_hexapod(), options);
  const double a = 1e-3;  // small noise: the linearised covariance is accurate
  const std::string loss_text = loss_name + ":" + std::to_string(2.5 * a / std::sqrt(3.0));
  const RobustLoss loss = RobustLoss::parse(loss_text);
  const auto solver = SolverRegistry::global().create("lm");
  SolverOptions solver_options;
  solver_options.loss = loss;
  solver_options.max_iterations = 200;
  const int trials = 150;
  const int n = static_cast<int>(exact.free_indices.size());
  MatrixXd estimates(trials, n);
  VectorXd mean_reported = VectorXd::Zero(n);
  Random rng(2024);
  for (int t = 0; t < trials; ++t) {
    Measurements data = exact.calibration;
    for (int j = 0; j < data.size(); ++j) data.readings(j, 0) += rng.symmetric(a);
    for (int k = 0; k < 3; ++k) {
      const int j = static_cast<int>(rng.uniform01() * data.size()) % data.size();
      data.readings(j, 0) += (rng.uniform01() < 0.5 ? -1 : 1) * 0.1 * (0.5 + rng.uniform01());
    }
    CalibrationProblem problem(exact.model, data, exact.nominal, exact.free_indices);
    // From the truth: Cauchy is not convex, and from far away it can stop in a local
    // minimum; where the solver ends is not what this test is about.
    VectorXd x(n);
    for (int i = 0; i < n; ++i) x[i] = exact.truth[exact.free_indices[i]];
    const Summary summary = solver->solve(problem, x, solver_options);
    ASSERT_NE(summary.termination, TerminationType::kFailed) << summary.message;
    estimates.row(t) = x.transpose();
    mean_reported +=
        make_calibration_report(problem, x, summary, {}, loss).uncertainty.std / trials;
  }
  double log_ratio_sum = 0;
  for (int i = 0; i < n; ++i) {
    const double ratio = mean_reported[i] / robust_spread(estimates.col(i));
    log_ratio_sum += std::log(ratio);
    // MAD of 150 draws has a relative standard error of ~10 %.
    EXPECT_GT(ratio, 0.7) << loss_text << " " << i;
    EXPECT_LT(ratio, 1.4) << loss_text << " " << i;
  }
  const double typical = std::exp(log_ratio_sum / n);
  EXPECT_GT(typical, 0.8) << loss_text;
  EXPECT_LT(typical, 1.2) << loss_text;
}

TEST(RobustUncertainty, HuberStdMatchesTheScatterWithOutliers) {
  expect_std_matches_scatter("huber");
}

TEST(RobustUncertainty, CauchyStdMatchesTheScatterWithOutliers) {
  expect_std_matches_scatter("cauchy");
}

}  // namespace
}  // namespace kincal
