// The fit check (framework/calibration/fit_check.hpp): the chi-square statistic of calibrate's
// report and of simulate, what it flags and what it leaves untested.

#include <gtest/gtest.h>

#include <cmath>

#include "kincal/framework/analysis/calibration_report.hpp"
#include "kincal/framework/analysis/validation.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/presets.hpp"

namespace kincal {
namespace {

CalibrationReport weighted_report(int dof) {
  CalibrationReport r;
  r.weighted = true;
  r.uncertainty.degrees_of_freedom = dof;
  return r;
}

TEST(FitCheck, ChiSquareIsTheSumOfSquaredWhitenedResidualsOnTheDegreesOfFreedom) {
  VectorXd whitened(4);
  whitened << 1.0, -2.0, 0.5, 3.0;
  const FitCheck f = check_fit(weighted_report(2), whitened);
  ASSERT_TRUE(f.tested) << f.not_tested;
  EXPECT_DOUBLE_EQ(f.chi_square, 1 + 4 + 0.25 + 9);
  EXPECT_EQ(f.degrees_of_freedom, 2);
  // Chi-square on 2 degrees of freedom: P(X >= x) = exp(-x / 2).
  EXPECT_NEAR(f.p_larger, std::exp(-14.25 / 2), 1e-12);
  EXPECT_FALSE(f.too_large());  // P = 8e-4
}

TEST(FitCheck, FlagsResidualsWhoseProbabilityIsBelowTheThreshold) {
  // On 2 degrees of freedom P = exp(-x / 2): x = 2 ln(1e4) = 18.42 is the threshold.
  const double threshold = -2 * std::log(kFitCheckProbability);
  VectorXd below(1), above(1);
  below << std::sqrt(threshold * 0.99);
  above << std::sqrt(threshold * 1.01);
  EXPECT_FALSE(check_fit(weighted_report(2), below).too_large());
  EXPECT_TRUE(check_fit(weighted_report(2), above).too_large());
}

TEST(FitCheck, SaysWhyItIsNotTested) {
  const VectorXd r = VectorXd::Constant(5, 10.0);  // far too large, were it tested
  CalibrationReport unweighted = weighted_report(3);
  unweighted.weighted = false;
  CalibrationReport with_prior = weighted_report(3);
  with_prior.prior = true;
  CalibrationReport robust = weighted_report(3);
  robust.loss = "huber:0.01";
  for (const CalibrationReport& report : {unweighted, with_prior, robust, weighted_report(0)}) {
    const FitCheck f = check_fit(report, r);
    EXPECT_FALSE(f.tested);
    EXPECT_FALSE(f.too_large());
    EXPECT_FALSE(f.not_tested.empty());
  }
  EXPECT_EQ(check_fit(unweighted, r).not_tested, kFitNoNoise);
}

ScenarioOptions case_options(int id, std::uint64_t seed) {
  ScenarioOptions o;
  o.noise_half_width.set(kincal::kMillimetre, paper_case(id).noise_half_width);
  o.num_configurations = paper_case(id).num_configurations;
  o.num_validation = 1;
  o.seed = seed;
  return o;
}

// At the least-squares minimum of the right model the statistic is chi-square on m - n: its
// mean over seeds is m - n (uniform noise has the same variance a^2 / 3 as assumed).
TEST(SimulatedFitCheck, AtTheMinimumOfTheRightModelItAveragesTheDegreesOfFreedom) {
  const auto model = make_cube_hexapod();
  const auto solver = SolverRegistry::global().create("lm");
  double sum = 0;
  int dof = 0;
  const int seeds = 40;
  for (int seed = 1; seed <= seeds; ++seed) {
    const Scenario s = make_scenario(model, case_options(5, seed));
    const CalibrationRun run = run_calibration(s, *solver, {}, false);
    const FitCheck f = simulated_fit_check(s, run);
    ASSERT_TRUE(f.tested) << f.not_tested;
    EXPECT_FALSE(f.too_large()) << "seed " << seed << ": P " << f.p_larger;
    sum += f.chi_square;
    dof = f.degrees_of_freedom;
  }
  EXPECT_EQ(dof, 60 - 24);
  // The mean of 40 draws of chi-square(36) has std sqrt(72 / 40) = 1.3.
  EXPECT_NEAR(sum / seeds, dof, 5.0);
}

TEST(SimulatedFitCheck, FlagsAnEstimateAwayFromTheMinimum) {
  const auto model = make_cube_hexapod();
  const Scenario s = make_scenario(model, case_options(3, 7));
  CalibrationRun run;
  run.estimate = s.truth;
  EXPECT_FALSE(simulated_fit_check(s, run).too_large());
  run.estimate[s.free_indices[0]] += 0.5;  // 0.5 mm off in one joint: a wrong geometry
  const FitCheck f = simulated_fit_check(s, run);
  ASSERT_TRUE(f.tested);
  EXPECT_TRUE(f.too_large()) << "P " << f.p_larger;
}

TEST(SimulatedFitCheck, IsNotTestedWithoutNoiseOrWithAPrior) {
  const auto model = make_cube_hexapod();
  const Scenario noise_free = make_scenario(model, case_options(1, 1));
  CalibrationRun run;
  run.estimate = noise_free.truth;
  EXPECT_FALSE(simulated_fit_check(noise_free, run).tested);
  ScenarioOptions o = case_options(3, 1);
  o.prior_std.set(kincal::kMillimetre, 2.887);
  const Scenario map = make_scenario(model, o);
  run.estimate = map.truth;
  const FitCheck f = simulated_fit_check(map, run);
  EXPECT_FALSE(f.tested);
  EXPECT_NE(f.not_tested.find("prior"), std::string::npos) << f.not_tested;
}

}  // namespace
}  // namespace kincal
