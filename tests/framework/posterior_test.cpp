// The posterior of a MAP estimate (estimate_posterior_uncertainty, data_share) and held-out
// validation (validate_held_out): closed forms on small problems, and the reported posterior
// std against the scatter of MAP estimates over seeds.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "kincal/framework/analysis/validation.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/calibration/prior_problem.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/framework/least_squares/uncertainty.hpp"
#include "kincal/models/presets.hpp"

namespace kincal {
namespace {

MatrixXd random_matrix(int rows, int cols, std::uint64_t seed) {
  Random rng(seed);
  MatrixXd A(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) A(i, j) = rng.symmetric(1.0);
  return A;
}

TEST(Posterior, MatchesTheClosedForm) {
  const MatrixXd J = random_matrix(12, 4, 3);
  const VectorXd r = random_matrix(12, 1, 4).col(0);
  const VectorXd precision = (VectorXd(4) << 4, 0, 0.25, 100).finished();
  const ParameterUncertainty u = estimate_posterior_uncertainty(J, r, precision);
  const MatrixXd JtJ = J.transpose() * J;
  const MatrixXd R1 = (JtJ + MatrixXd(precision.asDiagonal())).inverse() * JtJ;
  EXPECT_NEAR(u.effective_degrees_of_freedom, 12 - R1.trace(), 1e-12);
  const double s2 = r.squaredNorm() / (12 - R1.trace());
  EXPECT_NEAR(u.sigma * u.sigma, s2, 1e-12);
  const MatrixXd cov = (JtJ / s2 + MatrixXd(precision.asDiagonal())).inverse();
  EXPECT_LT((u.covariance - cov).cwiseAbs().maxCoeff(), 1e-12);
  const MatrixXd resolution = cov * JtJ / s2;
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(u.data_share[i], resolution(i, i), 1e-12) << i;
    EXPECT_NEAR(u.std[i], std::sqrt(cov(i, i)), 1e-12);
  }
  EXPECT_EQ(u.data_share[1], 1.0);  // no prior: all data
  EXPECT_LT(u.data_share[3], 0.5);  // a tight prior dominates
  EXPECT_EQ(u.prior_std[0], 0.5);
  EXPECT_EQ(u.prior_std[1], 0.0);
}

TEST(Posterior, WithoutAPriorIsThePlainUncertainty) {
  const MatrixXd J = random_matrix(12, 4, 5);
  const VectorXd r = random_matrix(12, 1, 6).col(0);
  const ParameterUncertainty a = estimate_posterior_uncertainty(J, r, VectorXd::Zero(4));
  const ParameterUncertainty b = estimate_uncertainty(J, r);
  EXPECT_EQ(a.std, b.std);
  EXPECT_EQ(a.sigma, b.sigma);
  EXPECT_EQ(a.effective_degrees_of_freedom, 8);
}

TEST(Posterior, AnUnseenParameterIsDeterminedByItsPrior) {
  MatrixXd J = random_matrix(12, 3, 7);
  J.col(2).setZero();
  const VectorXd precision = (VectorXd(3) << 0, 0, 1 / 9.0).finished();
  const ParameterUncertainty u =
      estimate_posterior_uncertainty(J, random_matrix(12, 1, 8).col(0), precision);
  EXPECT_NEAR(u.std[2], 3.0, 1e-12);  // the prior's std, untouched by the data
  EXPECT_NEAR(u.data_share[2], 0.0, 1e-12);
}

TEST(Posterior, RejectsARobustLossWithAPrior) {
  EXPECT_THROW(estimate_posterior_uncertainty(random_matrix(5, 2, 1), VectorXd::Zero(5),
                                              VectorXd::Ones(2), RobustLoss::parse("huber:1")),
               std::invalid_argument);
}

// Over seeds, the truth drawn from U[-5, 5] mm (std 5/sqrt(3), the prior's): the MAP
// estimate's error divided by the reported posterior std has RMS 1 (linearised; 200 seeds x 24
// parameters, the paper's case 4).
TEST(Posterior, ReportedStdMatchesTheErrorOverSeeds) {
  const auto solver = SolverRegistry::global().create("lm");
  double sum = 0;
  int count = 0;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    ScenarioOptions options;
    options.num_configurations = paper_case(4).num_configurations;
    options.noise_half_width.set(kincal::kMillimetre, paper_case(4).noise_half_width);
    options.prior_std.set(kincal::kMillimetre, 5 / std::sqrt(3.0));
    options.num_validation = 0;
    options.seed = seed;
    const Scenario scenario = make_scenario(make_cube_hexapod(), options);
    const CalibrationRun run = run_calibration(scenario, *solver, SolverOptions{}, false);
    ASSERT_TRUE(run.summary.converged()) << run.summary.brief_report();
    const auto problem = scenario.make_problem();
    const VectorXd x = problem->free_parameters(run.estimate);
    VectorXd r;
    MatrixXd J;
    ASSERT_TRUE(problem->evaluate(x, &r, &J));
    const ParameterUncertainty u =
        estimate_posterior_uncertainty(J, r, model_prior(*problem).precision());
    for (std::size_t i = 0; i < scenario.free_indices.size(); ++i) {
      const int p = scenario.free_indices[i];
      sum += std::pow((run.estimate[p] - scenario.truth[p]) / u.std[static_cast<int>(i)], 2);
      ++count;
    }
  }
  const double ratio = std::sqrt(sum / count);
  std::printf("RMS of (MAP - truth) / posterior std over 200 seeds x 24 parameters: %.3f\n", ratio);
  EXPECT_GT(ratio, 0.85);
  EXPECT_LT(ratio, 1.15);
}

TEST(Validation, ChiSquareTailHasKnownValues) {
  EXPECT_NEAR(chi_square_upper_tail(3.841458820694124, 1), 0.05, 1e-10);
  EXPECT_NEAR(chi_square_upper_tail(5.0, 2), std::exp(-2.5), 1e-14);
  EXPECT_NEAR(chi_square_upper_tail(124.342, 100), 0.05, 1e-5);
  EXPECT_NEAR(chi_square_upper_tail(77.9295, 100), 0.95, 1e-5);
  EXPECT_EQ(chi_square_upper_tail(0, 10), 1.0);
}

// Against closed forms (d1 = d2 = 2: 1 / (1 + f)) and scipy.stats.f.sf (scipy 1.10, Debian 12),
// on both sides of the continued fraction's switch.
TEST(Validation, FTailHasKnownValues) {
  for (double f : {0.01, 0.5, 1.0, 3.0, 40.0})
    EXPECT_NEAR(f_upper_tail(f, 2, 2), 1 / (1 + f), 1e-13);
  EXPECT_NEAR(f_upper_tail(4.6, 14, 2), 0.19271940001208432, 1e-12);
  EXPECT_NEAR(f_upper_tail(3.0, 5, 20), 0.03520133745266662, 1e-12);
  EXPECT_NEAR(f_upper_tail(0.5, 3, 7), 0.6940363875688136, 1e-12);
  EXPECT_NEAR(f_upper_tail(10, 1, 100), 0.0020728725808666576, 1e-12);
  // Many residual degrees of freedom: the chi-square tail of d1 F.
  EXPECT_NEAR(f_upper_tail(2.0, 4, 1e7), chi_square_upper_tail(8.0, 4), 1e-5);
  EXPECT_EQ(f_upper_tail(0, 3, 4), 1.0);
  EXPECT_EQ(f_upper_tail(HUGE_VAL, 3, 4), 0.0);
}

// The Woodbury form against the m x m covariance, on held-out data of the cube hexapod.
TEST(Validation, ChiSquareUsesTheFullCovariance) {
  ScenarioOptions options;
  options.num_configurations = 15;
  options.noise_half_width.set(kincal::kMillimetre, 0.0125);
  options.num_validation = 0;
  options.seed = 9;
  const Scenario scenario = make_scenario(make_cube_hexapod(), options);
  const std::vector<int> parameters(scenario.free_indices.begin(),
                                    scenario.free_indices.begin() + 5);
  const MatrixXd A = random_matrix(5, 5, 10);
  ValidationInput input;
  input.noise_std = VectorXd::Constant(1, 0.01);
  input.parameters = parameters;
  input.covariance = 0.01 * A * A.transpose();
  const Validation v =
      validate_held_out(scenario.model, scenario.calibration, scenario.truth, input);
  // Direct: r^T (D + J Sigma J^T)^-1 r.
  const CalibrationProblem problem(scenario.model, scenario.calibration, scenario.truth,
                                   parameters);
  VectorXd r;
  MatrixXd J;
  ASSERT_TRUE(problem.evaluate(problem.initial_free_parameters(), &r, &J));
  const MatrixXd C = 1e-4 * MatrixXd::Identity(15, 15) + J * input.covariance * J.transpose();
  const double expected = r.dot(C.ldlt().solve(r));
  EXPECT_NEAR(v.chi_square, expected, 1e-9 * expected);
  EXPECT_EQ(v.readings, 15);
  EXPECT_NEAR(v.standardized_rms, std::sqrt(expected / 15), 1e-9);
}

// With the true parameters and the true noise, held-out residuals are consistent; with the
// nominal model they are far larger than the noise predicts.
TEST(Validation, VerdictSeparatesTheTruthFromNominal) {
  ScenarioOptions options;
  options.num_configurations = 100;
  options.noise_half_width.set(kincal::kMillimetre, 0.0125);
  options.num_validation = 0;
  options.seed = 12;
  const Scenario scenario = make_scenario(make_cube_hexapod(), options);
  ValidationInput input;
  input.noise_std = VectorXd::Constant(1, 0.0125 / std::sqrt(3.0));
  const Validation truth =
      validate_held_out(scenario.model, scenario.calibration, scenario.truth, input);
  EXPECT_EQ(truth.verdict, "consistent") << truth.standardized_rms;
  EXPECT_NEAR(truth.standardized_rms, 1.0, 0.2);
  const Validation nominal =
      validate_held_out(scenario.model, scenario.calibration, scenario.nominal, input);
  EXPECT_EQ(nominal.verdict, "larger_than_predicted");
  EXPECT_GT(nominal.standardized_rms, 10);
}

// Calibrate (MAP) on 60 configurations, validate on 40 held out, over 100 seeds (case 5 noise,
// the prior the errors were drawn from): when noise and posterior are right, chi^2 / m
// averages 1 and the check says "consistent" about 99 % of the time.
TEST(Validation, HeldOutChiSquareAveragesOneAfterAMapCalibration) {
  const auto solver = SolverRegistry::global().create("lm");
  double sum = 0;
  int consistent = 0, runs = 0;
  for (std::uint64_t seed = 1; seed <= 100; ++seed) {
    ScenarioOptions options;
    options.num_configurations = 100;
    options.noise_half_width.set(kincal::kMillimetre, 0.0125);
    options.prior_std.set(kincal::kMillimetre, 5 / std::sqrt(3.0));
    options.num_validation = 0;
    options.seed = seed;
    const Scenario scenario = make_scenario(make_cube_hexapod(), options);
    Measurements fit, held_out;
    fit.actuators = scenario.calibration.actuators.topRows(60);
    fit.readings = scenario.calibration.readings.topRows(60);
    held_out.actuators = scenario.calibration.actuators.bottomRows(40);
    held_out.readings = scenario.calibration.readings.bottomRows(40);
    const CalibrationProblem problem(scenario.model, fit, scenario.nominal, scenario.free_indices);
    const Prior prior = model_prior(problem);
    VectorXd x = problem.initial_free_parameters();
    const Summary summary = solver->solve(PriorProblem(problem, prior), x, SolverOptions{});
    ASSERT_TRUE(summary.converged()) << summary.brief_report();
    VectorXd r;
    MatrixXd J;
    ASSERT_TRUE(problem.evaluate(x, &r, &J));
    const ParameterUncertainty u = estimate_posterior_uncertainty(J, r, prior.precision());
    ValidationInput input;
    input.noise_std = u.sigma * scenario.model->reading_std();
    input.parameters = scenario.free_indices;
    input.covariance = u.covariance;
    const Validation v =
        validate_held_out(scenario.model, held_out, problem.full_parameters(x), input);
    sum += v.chi_square / v.readings;
    consistent += v.verdict == "consistent";
    ++runs;
  }
  const double mean = sum / runs;
  std::printf("held-out chi^2 / m over %d seeds: mean %.3f, consistent in %d\n", runs, mean,
              consistent);
  EXPECT_NEAR(mean, 1.0, 0.1);
  EXPECT_GE(consistent, 95);
}

}  // namespace
}  // namespace kincal
