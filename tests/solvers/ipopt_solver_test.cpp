// ipopt on the paper's case 1 and on a small curve fit. Through the registry only, so this
// file builds with KINCAL_WITH_IPOPT=OFF too; then every test skips, saying so.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/presets.hpp"
#include "solver_fixtures.hpp"

namespace kincal {
namespace {

using kincal::testing::ExponentialFit;
using kincal::testing::FencedFit;
using kincal::testing::NowhereComputable;
using kincal::testing::paper_scenario;

std::unique_ptr<Solver> ipopt() { return SolverRegistry::global().create("ipopt"); }

class Ipopt : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string why = kincal::testing::why_not_built("ipopt");
    if (!why.empty()) GTEST_SKIP() << why;
  }
};

class IpoptCaseOne : public ::testing::TestWithParam<std::uint64_t> {
 protected:
  void SetUp() override {
    const std::string why = kincal::testing::why_not_built("ipopt");
    if (!why.empty()) GTEST_SKIP() << why;
  }
};

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

TEST_F(Ipopt, LimitedMemoryConverges) {
  // Ipopt's L-BFGS needs hundreds of iterations on the hexapod (cond(J^T J) ~ 1e10), so the
  // small fit stands in for it here.
  const ExponentialFit problem;
  SolverOptions options;
  options.max_iterations = 500;
  options.backend = ipopt()->parse_settings({{"hessian", "limited-memory"}});
  VectorXd x = ExponentialFit::start();
  const Summary summary = ipopt()->solve(problem, x, options);
  EXPECT_EQ(summary.termination, TerminationType::kConverged) << summary.brief_report();
  EXPECT_LT((x - ExponentialFit::solution()).lpNorm<Eigen::Infinity>(), 1e-6) << x.transpose();
}

TEST_F(Ipopt, BoundsAreHonoured) {
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

TEST_F(Ipopt, SilentUnlessVerbose) {
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

TEST_F(Ipopt, StopsAtTheIterationLimitAndSaysSo) {
  const Scenario scenario = paper_scenario(1, 3);
  SolverOptions options;
  options.max_iterations = 2;
  const CalibrationRun run = run_calibration(scenario, *ipopt(), options, false);
  EXPECT_EQ(run.summary.termination, TerminationType::kMaxIterations);
  EXPECT_EQ(run.summary.iterations, 2);
  EXPECT_EQ(run.summary.backend_code, -1);  // Maximum_Iterations_Exceeded
}

TEST_F(Ipopt, TraceAndCallbackAgreeAndTheCallbackCanStop) {
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

TEST_F(Ipopt, FailsWithTheReasonWhenTheStartIsNotComputable) {
  const NowhereComputable problem;
  VectorXd x = ExponentialFit::start();
  const Summary summary = ipopt()->solve(problem, x, {});
  EXPECT_EQ(summary.termination, TerminationType::kFailed);
  EXPECT_NE(summary.message.find("forward kinematics failed"), std::string::npos)
      << summary.message;
  EXPECT_EQ(x, ExponentialFit::start());
}

TEST_F(Ipopt, OptionsAreValidated) {
  const auto solver = ipopt();
  using kincal::testing::refuses;
  EXPECT_TRUE(refuses(*solver, {{"hessain", "gauss-newton"}}));
  EXPECT_TRUE(refuses(*solver, {{"hessian", "exact"}}));
  EXPECT_FALSE(refuses(
      *solver,
      {{"hessian", "limited-memory"}, {"mu_strategy", "adaptive"}, {"linear_solver", "mumps"}}));
}

// Trial points beyond the fence make Ipopt cut its step to ~1e-16 again and again; the
// backend stops it after 10 such iterations, calls that leaving the region, and names the
// reason Ipopt itself never hears.
TEST_F(Ipopt, StallingAgainstUncomputablePointsIsDivergenceWithTheReason) {
  const FencedFit problem;
  VectorXd x = FencedFit::start();
  SolverOptions options;
  options.max_iterations = 1000;
  const Summary summary = ipopt()->solve(problem, x, options);
  EXPECT_EQ(summary.termination, TerminationType::kDiverged) << summary.brief_report();
  EXPECT_NE(summary.message.find("10 iterations without progress"), std::string::npos)
      << summary.message;
  EXPECT_NE(summary.message.find(std::string("first: ") + FencedFit::kReason), std::string::npos)
      << summary.message;
  EXPECT_LT(summary.iterations, 100) << "it should stop long before max_iterations";
  EXPECT_LE(x[0], FencedFit::kFence);
  EXPECT_LT(summary.final_cost, 0.2 * summary.initial_cost);
  EXPECT_DOUBLE_EQ(summary.final_cost, problem.cost(x));
}

// A minimum inside the region, found although some trial points on the way fail: converged,
// with the failures still counted in the message.
TEST_F(Ipopt, FailedTrialPointsOnTheWayAreCountedInTheMessage) {
  class FenceOnTheWay : public ExponentialFit {
   public:
    bool evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                        Eigen::Ref<MatrixXd>* jacobian, std::string* why) const override {
      // The start has c = 0 and the minimum c = 0.3; Ipopt's first trial point (measured)
      // has c = 1.13, and its backtracked one c = 0.57.
      if (x[2] > 1.0) {
        if (why) *why = "c above 1";
        return false;
      }
      return ExponentialFit::evaluate_block(block, x, residuals, jacobian, why);
    }
  };
  const FenceOnTheWay problem;
  VectorXd x = ExponentialFit::start();
  const Summary summary = ipopt()->solve(problem, x, {});
  EXPECT_EQ(summary.termination, TerminationType::kConverged) << summary.brief_report();
  EXPECT_LT((x - ExponentialFit::solution()).lpNorm<Eigen::Infinity>(), 1e-6) << x.transpose();
  EXPECT_NE(summary.message.find("first: c above 1"), std::string::npos) << summary.message;
}

// Values that validate must work: a linear solver Ipopt cannot load is rejected by
// check_options (Debian's Ipopt has only MUMPS built in and loads HSL/Pardiso from
// libhsl.so/libpardiso.so), and one that is accepted solves the problem.
TEST_F(Ipopt, LinearSolversThatCannotBeLoadedAreRejectedUpFront) {
  for (const std::string linear : {"mumps", "ma27", "ma57", "ma77", "ma86", "ma97", "pardiso"}) {
    SolverOptions options;
    options.backend = ipopt()->parse_settings({{"linear_solver", linear}});
    try {
      ipopt()->check_options(options);
    } catch (const InvalidSolverOptions& e) {
      const std::string message = e.what();
      EXPECT_NE(linear, "mumps") << message;
      EXPECT_NE(message.find("linear_solver=" + linear + " is not available"), std::string::npos)
          << message;
      EXPECT_NE(message.find("mumps"), std::string::npos) << message;
      continue;
    }
    ::testing::internal::CaptureStdout();
    VectorXd x = ExponentialFit::start();
    const Summary summary = ipopt()->solve(ExponentialFit(), x, options);
    EXPECT_EQ(::testing::internal::GetCapturedStdout(), "") << linear;
    EXPECT_EQ(summary.termination, TerminationType::kConverged)
        << linear << " was accepted but: " << summary.brief_report();
  }
}

}  // namespace
}  // namespace kincal
