// The paper's Gauss-Newton on simulated data.

#include <gtest/gtest.h>

#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/presets.hpp"
#include "kincal/solvers/gauss_newton.hpp"
#include "solver_fixtures.hpp"

namespace kincal {
namespace {

using kincal::testing::paper_scenario;

class NoiseFreeCalibration : public ::testing::TestWithParam<std::uint64_t> {};

TEST_P(NoiseFreeCalibration, RecoversTheTrueParameters) {
  const Scenario scenario = paper_scenario(1, GetParam());
  const auto solver = SolverRegistry::global().create("gn");
  SolverOptions options;
  const CalibrationRun run = run_calibration(scenario, *solver, options, false);
  EXPECT_EQ(run.summary.termination, TerminationType::kConverged) << run.summary.brief_report();
  for (int i : scenario.free_indices)
    EXPECT_NEAR(run.estimate[i], scenario.truth[i], 1e-6) << scenario.model->parameters()[i].name;
  EXPECT_LT(run.after.position_max_mm, 1e-6);
  EXPECT_GT(run.before.position_mean_mm, 0.1);  // the starting model was really off
}

INSTANTIATE_TEST_SUITE_P(Seeds, NoiseFreeCalibration, ::testing::Values(1, 2, 3, 4, 5, 6, 7, 8));

TEST(GaussNewton, StopsAtTheIterationLimitAndSaysSo) {
  const Scenario scenario = paper_scenario(1, 3);
  const auto solver = SolverRegistry::global().create("gn");
  SolverOptions options;
  options.max_iterations = 1;
  const CalibrationRun run = run_calibration(scenario, *solver, options, false);
  EXPECT_EQ(run.summary.termination, TerminationType::kMaxIterations);
  EXPECT_EQ(run.summary.iterations, 1);
}

// The paper's method has no damping: from 40 mm parameter errors the first full step lands
// where forward kinematics fails for a configuration. That is `diverged`, with the reason.
TEST(GaussNewton, ReportsDivergedWhenForwardKinematicsFailsAtAnIterate) {
  const Scenario scenario = paper_scenario(1, 1, 40);
  const CalibrationRun run =
      run_calibration(scenario, *SolverRegistry::global().create("gn"), SolverOptions{}, false);
  EXPECT_EQ(run.summary.termination, TerminationType::kDiverged) << run.summary.brief_report();
  EXPECT_NE(run.summary.message.find("left the valid region"), std::string::npos);
  EXPECT_NE(run.summary.message.find("forward kinematics"), std::string::npos);
  EXPECT_EQ(run.summary.iterations, 1);
  EXPECT_EQ(run.summary.final_cost, run.summary.initial_cost);  // the start is the best point
}

TEST(GaussNewton, ReportsDivergedWhenTheParametersRunAway) {
  const Scenario scenario = paper_scenario(1, 3);
  SolverOptions options;
  // The first step moves some parameter by millimetres; allow 1e-3 * (1 + |x0|) ~ 0.3 mm.
  GaussNewtonSettings settings;
  settings.runaway_factor = 1e-3;
  options.backend = std::make_shared<GaussNewtonSettings>(settings);
  const CalibrationRun run =
      run_calibration(scenario, *SolverRegistry::global().create("gn"), options, false);
  EXPECT_EQ(run.summary.termination, TerminationType::kDiverged) << run.summary.brief_report();
  EXPECT_NE(run.summary.message.find("ran away"), std::string::npos) << run.summary.message;
  EXPECT_EQ(run.estimate, scenario.nominal);  // nothing was taken
}

// Undamped steps cannot stay in a box: bounds are refused rather than silently ignored.
TEST(GaussNewton, RejectsBounds) {
  const auto problem = paper_scenario(1, 3).make_problem();
  VectorXd x = problem->initial_free_parameters();
  const VectorXd start = x;
  SolverOptions options;
  options.lower_bounds = (x.array() - 10.0).matrix();
  options.upper_bounds = (x.array() + 10.0).matrix();
  const auto solver = SolverRegistry::global().create("gn");
  try {
    solver->solve(*problem, x, options);
    FAIL() << "bounds were accepted";
  } catch (const InvalidSolverOptions& e) {
    EXPECT_NE(std::string(e.what()).find("bounds are not supported"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(solver->check_options(options), InvalidSolverOptions);
  EXPECT_EQ(x, start);
}

}  // namespace
}  // namespace kincal
