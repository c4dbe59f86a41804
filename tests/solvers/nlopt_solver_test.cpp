// nlopt:<ALGORITHM> on the paper's case 1 and on a small curve fit.
#ifdef KINCAL_WITH_NLOPT

#include <gtest/gtest.h>

#include <cmath>

#include "framework/simulation.hpp"
#include "framework/solver_registry.hpp"
#include "models/presets.hpp"
#include "solver_fixtures.hpp"
#include "solvers/nlopt_solver.hpp"

namespace kincal {
namespace {

using kincal::testing::ExponentialFit;
using kincal::testing::NowhereComputable;
using kincal::testing::paper_scenario;

TEST(Nlopt, LbfgsRecoversCaseOneLoosely) {
  // First-order methods crawl on this problem (cond(J) ~ 1e5, so cond(J^T J) ~ 1e10): L-BFGS
  // stops on its own test with the cost down by 1e12 but the parameters only to ~0.1 mm.
  const Scenario scenario = paper_scenario(1, 1);
  const auto solver = SolverRegistry::global().create("nlopt:LD_LBFGS");
  SolverOptions options;
  options.max_iterations = 5000;  // objective evaluations
  const CalibrationRun run = run_calibration(scenario, *solver, options, false);
  EXPECT_EQ(run.summary.termination, TerminationType::kConverged) << run.summary.brief_report();
  EXPECT_LT(run.summary.final_cost, 1e-8 * run.summary.initial_cost);
  for (int i : scenario.free_indices)
    EXPECT_NEAR(run.estimate[i], scenario.truth[i], 0.3) << scenario.model->parameters()[i].name;
  EXPECT_LT(run.after.position_max_mm, 0.2);
  EXPECT_GT(run.before.position_mean_mm, 0.1);
}

TEST(Nlopt, SlsqpWithJacobianScalingRecoversCaseOneTightly) {
  const Scenario scenario = paper_scenario(1, 1);
  const auto solver = SolverRegistry::global().create("nlopt:LD_SLSQP");
  SolverOptions options;
  options.max_iterations = 5000;
  options.backend_options["scaling"] = "jacobian";
  const CalibrationRun run = run_calibration(scenario, *solver, options, false);
  EXPECT_EQ(run.summary.termination, TerminationType::kConverged) << run.summary.brief_report();
  for (int i : scenario.free_indices)
    EXPECT_NEAR(run.estimate[i], scenario.truth[i], 1e-6) << scenario.model->parameters()[i].name;
  EXPECT_LT(run.after.position_max_mm, 1e-6);
}

TEST(Nlopt, DerivativeFreeAlgorithmsFitASmallProblem) {
  const ExponentialFit problem;
  for (const std::string algorithm : {"LN_BOBYQA", "LN_NELDERMEAD", "LN_SBPLX", "LN_COBYLA"}) {
    const auto solver = make_nlopt_solver(algorithm);
    SolverOptions options;
    options.max_iterations = 20000;
    VectorXd x = ExponentialFit::start();
    const Summary summary = solver->solve(problem, x, options);
    EXPECT_EQ(summary.termination, TerminationType::kConverged) << summary.brief_report();
    EXPECT_LT((x - ExponentialFit::solution()).lpNorm<Eigen::Infinity>(), 1e-4)
        << algorithm << ": " << x.transpose();
    EXPECT_EQ(summary.jacobian_evaluations, 0) << algorithm;  // no derivatives asked for
  }
}

TEST(Nlopt, UnknownAlgorithmIsRejectedWithTheValidNames) {
  try {
    SolverRegistry::global().create("nlopt:LD_LBFGZ");
    FAIL() << "no exception";
  } catch (const InvalidSolverOptions& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("LD_LBFGZ"), std::string::npos) << message;
    for (const auto& name : nlopt_featured_algorithms())
      EXPECT_NE(message.find(name), std::string::npos) << message;
    EXPECT_NE(message.find("GN_DIRECT_L"), std::string::npos) << message;
  }
}

TEST(Nlopt, AnyNloptAlgorithmIsAccepted) {
  const auto solver = SolverRegistry::global().create("nlopt:LD_VAR2");
  EXPECT_EQ(solver->name(), "nlopt:LD_VAR2");
  const ExponentialFit problem;
  VectorXd x = ExponentialFit::start();
  SolverOptions options;
  options.max_iterations = 1000;
  const Summary summary = solver->solve(problem, x, options);
  EXPECT_EQ(summary.termination, TerminationType::kConverged) << summary.brief_report();
  EXPECT_LT((x - ExponentialFit::solution()).lpNorm<Eigen::Infinity>(), 1e-5);
}

TEST(Nlopt, GlobalAndAugmentedLagrangianAlgorithmsRunWithoutExtraSetup) {
  // Global algorithms get a box around x0 when no bounds are given; AUGLAG gets LD_LBFGS as
  // its subsidiary optimiser. Neither must end in NLopt's INVALID_ARGS.
  const ExponentialFit problem;
  for (const std::string algorithm : {"GN_DIRECT_L", "GN_CRS2_LM", "AUGLAG", "G_MLSL_LDS"}) {
    SolverOptions options;
    options.max_iterations = 300;
    VectorXd x = ExponentialFit::start();
    const Summary summary = make_nlopt_solver(algorithm)->solve(problem, x, options);
    EXPECT_NE(summary.termination, TerminationType::kFailed)
        << algorithm << ": " << summary.brief_report();
    EXPECT_LE(summary.final_cost, summary.initial_cost) << algorithm;
  }
}

TEST(Nlopt, MaxevalIsReportedAsTheIterationLimit) {
  const Scenario scenario = paper_scenario(1, 3);
  const auto solver = SolverRegistry::global().create("nlopt:LD_LBFGS");
  SolverOptions options;
  options.max_iterations = 10;
  int calls = 0;
  options.callback = [&](const IterationRecord&, const VectorXd&) {
    ++calls;
    return CallbackAction::kContinue;
  };
  const CalibrationRun run = run_calibration(scenario, *solver, options, false);
  EXPECT_EQ(run.summary.termination, TerminationType::kMaxIterations);
  EXPECT_EQ(run.summary.backend_code, 5);  // NLOPT_MAXEVAL_REACHED
  EXPECT_EQ(run.summary.iterations, 10);
  EXPECT_EQ(run.summary.residual_evaluations, 10);  // NLopt's first call reuses our start
  EXPECT_EQ(static_cast<int>(run.summary.trace.size()), calls);
  EXPECT_EQ(run.summary.trace.front().iteration, 0);
  EXPECT_LT(run.summary.final_cost, run.summary.initial_cost);
}

TEST(Nlopt, CallbackCanStop) {
  const ExponentialFit problem;
  SolverOptions options;
  int calls = 0;
  options.callback = [&](const IterationRecord&, const VectorXd&) {
    return ++calls == 3 ? CallbackAction::kStop : CallbackAction::kContinue;
  };
  VectorXd x = ExponentialFit::start();
  const Summary summary = make_nlopt_solver("LD_LBFGS")->solve(problem, x, options);
  EXPECT_EQ(summary.termination, TerminationType::kUserStopped) << summary.brief_report();
  EXPECT_EQ(calls, 3);
  EXPECT_EQ(summary.trace.size(), 3u);
  EXPECT_DOUBLE_EQ(summary.final_cost, summary.trace.back().cost);
}

TEST(Nlopt, FailsWithTheReasonWhenTheStartIsNotComputable) {
  const NowhereComputable problem;
  VectorXd x = ExponentialFit::start();
  const Summary summary = make_nlopt_solver("LN_BOBYQA")->solve(problem, x, {});
  EXPECT_EQ(summary.termination, TerminationType::kFailed);
  EXPECT_NE(summary.message.find("forward kinematics failed"), std::string::npos)
      << summary.message;
  EXPECT_EQ(x, ExponentialFit::start());
}

TEST(Nlopt, BoundsAreHonoured) {
  const ExponentialFit problem;
  SolverOptions options;
  options.max_iterations = 2000;
  options.lower_bounds = Eigen::Vector3d(0, 0, 0);
  options.upper_bounds = Eigen::Vector3d(1.5, 2, 1);  // a < 2: the solution is outside
  for (const std::string algorithm : {"LD_MMA", "LN_BOBYQA"}) {
    VectorXd x = ExponentialFit::start();
    const Summary summary = make_nlopt_solver(algorithm)->solve(problem, x, options);
    EXPECT_EQ(summary.termination, TerminationType::kConverged) << summary.brief_report();
    EXPECT_TRUE((x.array() >= options.lower_bounds->array()).all()) << x.transpose();
    EXPECT_TRUE((x.array() <= options.upper_bounds->array()).all()) << x.transpose();
    EXPECT_NEAR(x[0], 1.5, 1e-6) << algorithm;  // pressed against the bound
  }
}

TEST(Nlopt, OptionsAreValidated) {
  const auto solver = make_nlopt_solver("LD_LBFGS");
  SolverOptions options;
  options.backend_options["initial_stepp"] = "1";
  EXPECT_THROW(solver->check_options(options), InvalidSolverOptions);
  options.backend_options = {{"initial_step", "-1"}};
  EXPECT_THROW(solver->check_options(options), InvalidSolverOptions);
  options.backend_options = {{"local_algorithm", "LN_BOBYQA"}};  // LBFGS has no subsidiary
  EXPECT_THROW(solver->check_options(options), InvalidSolverOptions);
  options.backend_options = {{"scaling", "jacobian"}, {"initial_step", "0.5"}, {"seed", "3"}};
  EXPECT_NO_THROW(solver->check_options(options));
  options.backend_options = {{"local_algorithm", "GN_DIRECT"}};
  EXPECT_THROW(make_nlopt_solver("AUGLAG")->check_options(options), InvalidSolverOptions);
  options.backend_options = {{"local_algorithm", "LN_BOBYQA"}};
  EXPECT_NO_THROW(make_nlopt_solver("AUGLAG")->check_options(options));
}

}  // namespace
}  // namespace kincal

#endif  // KINCAL_WITH_NLOPT
