// ipopt on the paper's case 1 and on a small curve fit.
#ifdef KINCAL_WITH_IPOPT

#include <gtest/gtest.h>

#include <cmath>

#include "framework/simulation.hpp"
#include "framework/solver_registry.hpp"
#include "models/presets.hpp"
#include "solver_fixtures.hpp"

namespace kincal {
namespace {

using kincal::testing::ExponentialFit;
using kincal::testing::NowhereComputable;
using kincal::testing::paper_scenario;

std::unique_ptr<Solver> ipopt() { return SolverRegistry::global().create("ipopt"); }

class IpoptCaseOne : public ::testing::TestWithParam<std::uint64_t> {};

TEST_P(IpoptCaseOne, GaussNewtonHessianRecoversTheTrueParameters) {
  const Scenario scenario = paper_scenario(1, GetParam());
  const CalibrationRun run = run_calibration(scenario, *ipopt(), {}, false);
  EXPECT_EQ(run.summary.termination, TerminationType::kConverged) << run.summary.brief_report();
  for (int i : scenario.free_indices)
    EXPECT_NEAR(run.estimate[i], scenario.truth[i], 1e-6) << scenario.model->parameters()[i].name;
  EXPECT_LT(run.after.position_max_mm, 1e-6);
  EXPECT_LT(run.summary.iterations, 20);
  EXPECT_EQ(run.summary.residual_evaluations, run.summary.jacobian_evaluations);
}

INSTANTIATE_TEST_SUITE_P(Seeds, IpoptCaseOne, ::testing::Values(1, 2, 3));

TEST(Ipopt, LimitedMemoryConverges) {
  // Ipopt's L-BFGS needs hundreds of iterations on the hexapod (cond(J^T J) ~ 1e10), so the
  // small fit stands in for it here.
  const ExponentialFit problem;
  SolverOptions options;
  options.max_iterations = 500;
  options.backend_options["hessian"] = "limited-memory";
  VectorXd x = ExponentialFit::start();
  const Summary summary = ipopt()->solve(problem, x, options);
  EXPECT_EQ(summary.termination, TerminationType::kConverged) << summary.brief_report();
  EXPECT_LT((x - ExponentialFit::solution()).lpNorm<Eigen::Infinity>(), 1e-6) << x.transpose();
}

TEST(Ipopt, BoundsAreHonoured) {
  const Scenario scenario = paper_scenario(1, 2);
  const auto problem = scenario.make_problem();
  const VectorXd x0 = problem->initial_free_parameters();
  SolverOptions options;
  options.lower_bounds = (x0.array() - 1.0).matrix();  // the truth is up to 5 mm away
  options.upper_bounds = (x0.array() + 1.0).matrix();
  VectorXd x = x0;
  const Summary summary = ipopt()->solve(*problem, x, options);
  EXPECT_NE(summary.termination, TerminationType::kFailed) << summary.brief_report();
  EXPECT_TRUE((x.array() >= options.lower_bounds->array()).all());
  EXPECT_TRUE((x.array() <= options.upper_bounds->array()).all());
  EXPECT_LT(summary.final_cost, summary.initial_cost);
  // Some parameter ends on its bound (to within Ipopt's interior-point margin).
  const double slack =
      std::min((x - *options.lower_bounds).minCoeff(), (*options.upper_bounds - x).minCoeff());
  EXPECT_LT(slack, 1e-6);
}

TEST(Ipopt, SilentUnlessVerbose) {
  const Scenario scenario = paper_scenario(1, 1);
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  const CalibrationRun run = run_calibration(scenario, *ipopt(), {}, false);
  const std::string out = ::testing::internal::GetCapturedStdout();
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_TRUE(run.summary.converged());
  EXPECT_EQ(out, "");
  EXPECT_EQ(err, "");
}

TEST(Ipopt, StopsAtTheIterationLimitAndSaysSo) {
  const Scenario scenario = paper_scenario(1, 3);
  SolverOptions options;
  options.max_iterations = 2;
  const CalibrationRun run = run_calibration(scenario, *ipopt(), options, false);
  EXPECT_EQ(run.summary.termination, TerminationType::kMaxIterations);
  EXPECT_EQ(run.summary.iterations, 2);
  EXPECT_EQ(run.summary.backend_code, -1);  // Maximum_Iterations_Exceeded
}

TEST(Ipopt, TraceAndCallbackAgreeAndTheCallbackCanStop) {
  const ExponentialFit problem;
  SolverOptions options;
  int calls = 0;
  options.callback = [&](const IterationRecord& record, const VectorXd& x) {
    EXPECT_EQ(record.iteration, calls);
    EXPECT_NEAR(record.cost, problem.cost(x), 1e-12 * (1 + record.cost));
    return ++calls == 3 ? CallbackAction::kStop : CallbackAction::kContinue;
  };
  VectorXd x = ExponentialFit::start();
  const Summary summary = ipopt()->solve(problem, x, options);
  EXPECT_EQ(summary.termination, TerminationType::kUserStopped) << summary.brief_report();
  EXPECT_EQ(calls, 3);
  ASSERT_EQ(summary.trace.size(), 3u);
  EXPECT_EQ(summary.trace.front().iteration, 0);
  EXPECT_DOUBLE_EQ(summary.final_cost, summary.trace.back().cost);
}

TEST(Ipopt, FailsWithTheReasonWhenTheStartIsNotComputable) {
  const NowhereComputable problem;
  VectorXd x = ExponentialFit::start();
  const Summary summary = ipopt()->solve(problem, x, {});
  EXPECT_EQ(summary.termination, TerminationType::kFailed);
  EXPECT_NE(summary.message.find("forward kinematics failed"), std::string::npos)
      << summary.message;
  EXPECT_EQ(x, ExponentialFit::start());
}

TEST(Ipopt, OptionsAreValidated) {
  const auto solver = ipopt();
  SolverOptions options;
  options.backend_options["hessain"] = "gauss-newton";
  EXPECT_THROW(solver->check_options(options), InvalidSolverOptions);
  options.backend_options = {{"hessian", "exact"}};
  EXPECT_THROW(solver->check_options(options), InvalidSolverOptions);
  options.backend_options = {
      {"hessian", "limited-memory"}, {"mu_strategy", "adaptive"}, {"linear_solver", "mumps"}};
  EXPECT_NO_THROW(solver->check_options(options));
}

}  // namespace
}  // namespace kincal

#endif  // KINCAL_WITH_IPOPT
