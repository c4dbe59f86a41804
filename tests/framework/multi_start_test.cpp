// Several starts of one problem (framework/calibration/multi_start.hpp): the draws, the grouping
// into distinct minima, independence of the thread count, and the hexapod's far-start minima.

#include "kincal/framework/calibration/multi_start.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/presets.hpp"

namespace kincal {
namespace {

// r = (x0^2 - 1, 0.3 (x0 - 1), x1 - 2): the global minimum at x0 = 1 (cost 0) and a local one
// near x0 = -0.95 (cost about 0.18), separated by a ridge near x0 = 0.
class TwoMinima : public LeastSquaresProblem {
 public:
  int num_parameters() const override { return 2; }
  int num_residual_blocks() const override { return 1; }
  int residuals_per_block() const override { return 3; }
  bool evaluate_block(int, const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                      std::string*) const override {
    r << x[0] * x[0] - 1, 0.3 * (x[0] - 1), x[1] - 2;
    if (J) *J << 2 * x[0], 0, 0.3, 0, 0, 1;
    return true;
  }
};

StartSpread uniform_spread(double a, double b) {
  StartSpread s;
  s.half_width = Eigen::Vector2d(a, b);
  s.std = VectorXd::Zero(2);
  return s;
}

MultiStartOptions options(int starts, int threads) {
  MultiStartOptions o;
  o.starts = starts;
  o.seed = 11;
  o.threads = threads;
  o.spread = uniform_spread(3.0, 1.0);
  return o;
}

TEST(DrawStart, StartZeroIsTheGivenPointAndTheOthersLieInTheSpread) {
  const Eigen::Vector2d x0(-1.5, 0.5);
  const StartSpread spread = uniform_spread(3.0, 1.0);
  EXPECT_EQ(draw_start(x0, spread, 5, 0), VectorXd(x0));
  for (int k = 1; k < 200; ++k) {
    const VectorXd x = draw_start(x0, spread, 5, k);
    EXPECT_LE(std::abs(x[0] - x0[0]), 3.0);
    EXPECT_LE(std::abs(x[1] - x0[1]), 1.0);
    EXPECT_EQ(x, draw_start(x0, spread, 5, k));  // a function of (seed, k)
    EXPECT_NE(x, draw_start(x0, spread, 6, k));
  }
}

TEST(DrawStart, GaussianWhereOnlyAStdIsGiven) {
  StartSpread spread;
  spread.half_width = VectorXd::Zero(1);
  spread.std = VectorXd::Constant(1, 2.0);
  const VectorXd x0 = VectorXd::Zero(1);
  double sum = 0, sum2 = 0;
  const int n = 4000;
  for (int k = 1; k <= n; ++k) {
    const double v = draw_start(x0, spread, 3, k)[0];
    sum += v;
    sum2 += v * v;
  }
  EXPECT_NEAR(sum / n, 0.0, 0.15);             // std of the mean: 2 / sqrt(4000) = 0.03
  EXPECT_NEAR(std::sqrt(sum2 / n), 2.0, 0.1);  // std of the std: about 0.02
  EXPECT_NEAR(spread.scale()[0], 2.0, 0);
  EXPECT_NEAR(uniform_spread(3.0, 1.0).scale()[0], 3.0 / std::sqrt(3.0), 1e-15);
}

TEST(MultiStart, FindsBothMinimaAndContinuesWithTheLowest) {
  const TwoMinima problem;
  const auto lm = SolverRegistry::global().create("lm");
  const MultiStartResult m =
      solve_multi_start(problem, *lm, Eigen::Vector2d(-1.5, 0.5), {}, options(12, 2));
  ASSERT_EQ(m.starts.size(), 12u);
  ASSERT_EQ(m.minima.size(), 2u);
  EXPECT_NEAR(m.minima[0].x[0], 1.0, 1e-6);
  EXPECT_NEAR(m.minima[0].cost, 0.0, 1e-12);
  EXPECT_NEAR(m.minima[1].x[0], -0.954, 0.01);
  EXPECT_GT(m.minima[1].cost, 0.1);
  EXPECT_GT(m.minima[1].distance_to_best, 0.5);
  EXPECT_EQ(m.minima[0].distance_to_best, 0.0);
  // Start 0 (x0 = -1.5) ends in the local minimum; the estimate is the first start at the
  // global one.
  EXPECT_EQ(m.starts[0].minimum, 1);
  EXPECT_NE(m.best_start, 0);
  EXPECT_EQ(m.best_start, m.minima[0].starts.front());
  std::size_t grouped = 0;
  for (const DistinctMinimum& d : m.minima) {
    EXPECT_TRUE(std::is_sorted(d.starts.begin(), d.starts.end()));
    grouped += d.starts.size();
    for (int k : d.starts) EXPECT_EQ(m.starts[k].minimum, &d - m.minima.data());
  }
  EXPECT_EQ(grouped + m.unsolved, m.starts.size());
}

TEST(MultiStart, TheResultDoesNotDependOnTheThreadCount) {
  const TwoMinima problem;
  const auto lm = SolverRegistry::global().create("lm");
  const Eigen::Vector2d x0(-1.5, 0.5);
  const MultiStartResult one = solve_multi_start(problem, *lm, x0, {}, options(9, 1));
  const MultiStartResult three = solve_multi_start(problem, *lm, x0, {}, options(9, 3));
  EXPECT_EQ(one.best_start, three.best_start);
  ASSERT_EQ(one.minima.size(), three.minima.size());
  for (std::size_t i = 0; i < one.minima.size(); ++i) {
    EXPECT_EQ(one.minima[i].starts, three.minima[i].starts);
    EXPECT_EQ(one.minima[i].x, three.minima[i].x);  // bit for bit
    EXPECT_EQ(one.minima[i].cost, three.minima[i].cost);
  }
}

TEST(MultiStart, OneStartIsTheSolveFromTheGivenPoint) {
  const TwoMinima problem;
  const auto lm = SolverRegistry::global().create("lm");
  VectorXd x = Eigen::Vector2d(-1.5, 0.5);
  const Summary alone = lm->solve(problem, x, {});
  const MultiStartResult m =
      solve_multi_start(problem, *lm, Eigen::Vector2d(-1.5, 0.5), {}, options(1, 0));
  ASSERT_EQ(m.minima.size(), 1u);
  EXPECT_EQ(m.best_start, 0);
  EXPECT_EQ(m.starts[0].x, x);
  EXPECT_EQ(m.starts[0].summary.final_cost, alone.final_cost);
}

TEST(MultiStart, TheCallbackSeesEveryStartAndItsStopStopsThemAll) {
  const TwoMinima problem;
  const auto lm = SolverRegistry::global().create("lm");
  const Eigen::Vector2d x0(-1.5, 0.5);
  // Called one call at a time: a plain counter is safe.
  int calls = 0;
  SolverOptions watched;
  watched.callback = [&](const IterationRecord&, const VectorXd&) {
    ++calls;
    return CallbackAction::kContinue;
  };
  const MultiStartResult all = solve_multi_start(problem, *lm, x0, watched, options(12, 2));
  EXPECT_FALSE(all.stopped);
  EXPECT_GE(calls, 24);  // every start reports iteration 0 and at least one iterate
  EXPECT_EQ(all.estimate_summary().termination, TerminationType::kConverged);

  calls = 0;
  SolverOptions stopping;
  stopping.callback = [&](const IterationRecord&, const VectorXd&) {
    return ++calls >= 5 ? CallbackAction::kStop : CallbackAction::kContinue;
  };
  const MultiStartResult stopped = solve_multi_start(problem, *lm, x0, stopping, options(12, 2));
  EXPECT_TRUE(stopped.stopped);
  EXPECT_EQ(calls, 5);  // not asked again once it said stop
  int user_stopped = 0;
  for (const StartOutcome& o : stopped.starts)
    user_stopped += o.summary.termination == TerminationType::kUserStopped;
  // Four calls before the stop: at most two starts can have ended on their own.
  EXPECT_GE(user_stopped, 10);
  const Summary summary = stopped.estimate_summary();
  EXPECT_EQ(summary.termination, TerminationType::kUserStopped);
  EXPECT_NE(summary.message.find("before every start had ended"), std::string::npos);
  EXPECT_LE(summary.final_cost, summary.initial_cost);
}

TEST(MultiStart, RefusesNoStartsAndASpreadOfAnotherSize) {
  const TwoMinima problem;
  const auto lm = SolverRegistry::global().create("lm");
  const Eigen::Vector2d x0(0.5, 0.5);
  EXPECT_THROW(solve_multi_start(problem, *lm, x0, {}, options(0, 1)), std::invalid_argument);
  MultiStartOptions wrong = options(3, 1);
  wrong.spread.half_width = VectorXd::Ones(3);
  EXPECT_THROW(solve_multi_start(problem, *lm, x0, {}, wrong), std::invalid_argument);
}

// docs/benchmarks.md, "Local minima": case 2 with +-20 mm errors, seed 16. lm from nominal
// converges to a minimum whose residuals are as small as the noise; one of 8 starts finds a
// lower one.
TEST(MultiStart, FindsALowerMinimumOfTheHexapodFromFarStarts) {
  ScenarioOptions o;
  o.noise_half_width.set(kincal::kMillimetre, paper_case(2).noise_half_width);
  o.num_configurations = paper_case(2).num_configurations;
  o.param_error_half_width.set(kincal::kMillimetre, 20);
  o.num_validation = 1;
  o.seed = 16;
  const Scenario scenario = make_scenario(make_cube_hexapod(), o);
  const auto lm = SolverRegistry::global().create("lm");
  const MultiStartResult m = solve_scenario_starts(scenario, *lm, {}, 8, 2);
  ASSERT_GE(m.minima.size(), 2u);
  EXPECT_NE(m.best_start, 0);
  const StartOutcome& first = m.starts[0];
  ASSERT_TRUE(reached_solution(first.summary));
  EXPECT_LT(m.minima[0].cost, first.summary.final_cost * (1 - 1e-4));
  EXPECT_GE(m.minima[first.minimum].starts.size(), 2u);      // a basin, not a stray stop
  EXPECT_GT(m.minima[first.minimum].distance_to_best, 0.1);  // 0.1 spread = 1.2 mm RMS
  // The fit check cannot tell start 0's minimum from the lowest: both fit to the noise.
  CalibrationRun run;
  const auto problem = scenario.make_problem();
  run.estimate = problem->full_parameters(first.x);
  EXPECT_FALSE(simulated_fit_check(scenario, run).too_large());
}

}  // namespace
}  // namespace kincal
