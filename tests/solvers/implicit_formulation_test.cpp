// The implicit-loop formulation (poses as unknowns): its Jacobian against finite differences,
// the Schur-complement step against the dense normal equations, the same estimates as the
// nested formulation on the paper's cases, and failures and fall-backs reported (a failed
// implicit solve replaced by the nested one).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "jacobian_check.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/calibration/calibration_solve.hpp"
#include "kincal/framework/calibration/implicit_calibration_problem.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/framework/least_squares/stationarity.hpp"
#include "kincal/models/presets.hpp"
#include "kincal/solvers/levenberg_marquardt.hpp"
#include "kincal/solvers/schur_levenberg_marquardt.hpp"
#include "newton_polish.hpp"
#include "solver_fixtures.hpp"

namespace kincal {
namespace {

using kincal::testing::paper_scenario;

Scenario preset_scenario(const std::string& preset, int configurations, std::uint64_t seed) {
  ScenarioOptions options;
  options.num_configurations = configurations;
  options.noise_half_width.set(kincal::kMillimetre, 0.01);
  options.num_validation = 0;
  options.seed = seed;
  return make_scenario(make_preset(preset), options);
}

// x with the parameters moved from nominal and every pose moved off its reference, so that
// the closure constraints, the chart's rotation and the readings all contribute.
VectorXd perturbed_x(const ImplicitCalibrationProblem& problem, std::uint64_t seed) {
  Random rng(seed);
  VectorXd x = problem.initial_x();
  for (int i = 0; i < x.size(); ++i) x[i] += rng.symmetric(0.05);
  return x;
}

class ImplicitJacobian : public ::testing::TestWithParam<std::string> {};

TEST_P(ImplicitJacobian, MatchesCentralDifferences) {
  const Scenario scenario = preset_scenario(GetParam(), 6, 3);
  const ImplicitCalibrationProblem problem(scenario.make_problem(), 10.0);
  const VectorXd x = perturbed_x(problem, 11);
  VectorXd r;
  MatrixXd J;
  std::string why;
  ASSERT_TRUE(problem.evaluate(x, &r, &J, &why)) << why;
  const MatrixXd numeric = testing::numerical_jacobian(
      [&](const VectorXd& at) {
        VectorXd out;
        EXPECT_TRUE(problem.evaluate(at, &out, nullptr));
        return out;
      },
      x, 1e-6);
  EXPECT_TRUE(testing::jacobians_match(J, numeric, 1e-6, problem.parameter_names()));
  // Both kinds of rows, and both kinds of columns, carry derivatives.
  const int dof = problem.dof(), p = problem.num_free_parameters();
  EXPECT_GT(J.topLeftCorner(dof, p).norm(), 0);  // constraints / params
  EXPECT_GT(J.block(0, p, dof, dof).norm(), 0);  // constraints / pose 1
  EXPECT_GT(J.block(dof, p, problem.residuals_per_block() - dof, dof).norm(), 0);  // readings
}

// One configuration's blocks (what a block-structured backend asks for, one Jacobian at a
// time) are its rows of the whole problem's, whose derivatives the test above checks.
TEST_P(ImplicitJacobian, OneConfigurationsBlocksAreItsRowsOfTheWholeJacobian) {
  const Scenario scenario = preset_scenario(GetParam(), 6, 3);
  const ImplicitCalibrationProblem problem(scenario.make_problem(), 10.0);
  const VectorXd x = perturbed_x(problem, 12);
  VectorXd r;
  MatrixXd J;
  ASSERT_TRUE(problem.evaluate(x, &r, &J));
  const int dof = problem.dof(), p = problem.num_free_parameters();
  const int k = problem.residuals_per_block();
  const VectorXd theta = x.head(p);
  for (int j = 0; j < problem.num_residual_blocks(); ++j) {
    const VectorXd local = x.segment(p + dof * j, dof);
    VectorXd residuals(k);
    MatrixXd J_theta(k, p), J_local(k, dof);
    Eigen::Ref<MatrixXd> theta_ref(J_theta), local_ref(J_local);
    std::string why;
    ASSERT_TRUE(
        problem.evaluate_configuration(j, theta, local, residuals, nullptr, &local_ref, &why))
        << why;
    EXPECT_EQ(J_local, J.block(k * j, p + dof * j, k, dof)) << "configuration " << j;
    ASSERT_TRUE(
        problem.evaluate_configuration(j, theta, local, residuals, &theta_ref, nullptr, &why))
        << why;
    EXPECT_EQ(J_theta, J.block(k * j, 0, k, p)) << "configuration " << j;
    EXPECT_EQ(residuals, r.segment(k * j, k)) << "configuration " << j;
    // Every other pose's columns are zero in the whole Jacobian.
    MatrixXd other_poses = J.middleRows(k * j, k).rightCols(dof * problem.num_residual_blocks());
    other_poses.middleCols(dof * j, dof).setZero();
    EXPECT_EQ(other_poses.norm(), 0.0) << "configuration " << j;
  }
}

INSTANTIATE_TEST_SUITE_P(ClosedChains, ImplicitJacobian,
                         ::testing::Values("cube-hexapod", "stewart-6-6", "planar-3rpr"));

TEST(ImplicitFormulation, StartsWhereTheClosureHoldsWithTheNestedCost) {
  const Scenario scenario = paper_scenario(3, 7);
  const auto nested = scenario.make_problem();
  const ImplicitCalibrationProblem problem(nested);
  VectorXd r;
  ASSERT_TRUE(problem.evaluate(problem.initial_x(), &r, nullptr));
  const double nested_cost = nested->cost(nested->initial_free_parameters());
  EXPECT_NEAR(0.5 * r.squaredNorm(), nested_cost, 1e-9 * nested_cost);
}

TEST(ImplicitFormulation, SchurStepEqualsTheDenseNormalEquationsStep) {
  for (const std::string preset : {"cube-hexapod", "planar-3rpr"}) {
    const Scenario scenario = preset_scenario(preset, 8, 5);
    // A small weight so that the closure rows' coupling with the readings matters.
    const ImplicitCalibrationProblem problem(scenario.make_problem(), 3.0);
    VectorXd x = problem.initial_x();
    Random rng(17);
    for (int i = 0; i < problem.num_free_parameters(); ++i) x[i] += rng.symmetric(0.5);
    VectorXd r;
    MatrixXd J;
    ASSERT_TRUE(problem.evaluate(x, &r, &J));
    const int p = problem.num_free_parameters();
    VectorXd damping(p);
    for (int i = 0; i < p; ++i) damping[i] = 0.1 + 1.9 * rng.uniform01();
    MatrixXd normal = J.transpose() * J;
    normal.diagonal().head(p) += damping;
    const VectorXd dense = -normal.ldlt().solve(J.transpose() * r);
    const VectorXd schur = implicit_schur_step(problem, x, damping);
    EXPECT_LE((schur - dense).lpNorm<Eigen::Infinity>(),
              1e-8 * (1 + dense.lpNorm<Eigen::Infinity>()))
        << preset << ": dense " << dense.head(4).transpose() << " schur "
        << schur.head(4).transpose();
  }
}

// The paper's five cases, a few seeds each (200 seeds: benchmarks/implicit_agreement.cpp).
// Tight tolerances, as the backends' agreement test (conformance_test.cpp). Even so, both
// formulations stop anywhere in the valley where the cost no longer changes by more than its
// rounding error (cond(J) ~ 1e5): up to ~4e-4 mm from the minimum, measured. The minimum
// itself is resolved to ~1e-8 mm by Newton steps from either end point
// (tests/newton_polish.hpp), and there the two agree.
SolverOptions tight() {
  SolverOptions options;
  options.max_iterations = 500;
  options.function_tolerance = 1e-16;
  options.parameter_tolerance = 1e-14;
  options.gradient_tolerance = 1e-13;
  return options;
}

TEST(ImplicitFormulation, ReachesTheNestedMinimumOnThePaperCases) {
  const auto lm = SolverRegistry::global().create("lm");
  const SolverOptions options = tight();
  for (int case_id = 1; case_id <= 5; ++case_id) {
    for (std::uint64_t seed : {1u, 2u, 3u}) {
      const Scenario scenario = paper_scenario(case_id, seed, 5, 0);
      const auto problem = scenario.make_problem();
      const Prior none = model_prior(*problem);
      VectorXd nested_x = problem->initial_free_parameters(), implicit_x = nested_x;
      const CalibrationSolve nested =
          solve_calibration(*lm, *problem, none, nested_x, options, Formulation::kNested);
      const CalibrationSolve implicit =
          solve_calibration(*lm, *problem, none, implicit_x, options, Formulation::kImplicit);
      const std::string where = "case " + std::to_string(case_id) + " seed " + std::to_string(seed);
      ASSERT_EQ(implicit.formulation, Formulation::kImplicit) << implicit.note;
      EXPECT_TRUE(nested.summary.converged()) << where << ": " << nested.summary.message;
      EXPECT_TRUE(implicit.summary.converged()) << where << ": " << implicit.summary.message;
      // The cost reported is the nested problem's at the x returned, to the cost's rounding:
      // its forward kinematics starts from the solve's closed poses (as nested lm's from its
      // last ones), so the readings' last bits differ from a cold evaluation's (by ~1e-10 of
      // the cost where the residuals are 1e-4 of the 600 mm lengths they are differences of).
      VectorXd r;
      MatrixXd J;
      ASSERT_TRUE(problem->evaluate(implicit_x, &r, &J));
      const double cold = 0.5 * r.squaredNorm();
      EXPECT_NEAR(implicit.summary.final_cost, cold, 1e-12 * cold + cost_rounding(implicit_x, r, J))
          << where;
      // As low as nested's, to the cost's rounding (case 1's noise-free minimum: ~1e-25).
      EXPECT_LE(implicit.summary.final_cost, nested.summary.final_cost * (1 + 1e-9) + 1e-20)
          << where;
      EXPECT_LE((implicit_x - nested_x).lpNorm<Eigen::Infinity>(), 1e-4) << where;
      double last_step_nested = 0, last_step_implicit = 0;
      const VectorXd minimum_from_nested =
          testing::newton_polished(*problem, nested_x, &last_step_nested);
      const VectorXd minimum_from_implicit =
          testing::newton_polished(*problem, implicit_x, &last_step_implicit);
      // Both polishings converged (their steps shrank to rounding) ...
      EXPECT_LE(std::max(last_step_nested, last_step_implicit), 1e-7) << where;
      // ... to the same minimum.
      EXPECT_LE((minimum_from_implicit - minimum_from_nested).lpNorm<Eigen::Infinity>(), 1e-6)
          << where;
    }
  }
}

TEST(ImplicitFormulation, ForwardKinematicsFailingAtTheStartIsReported) {
  Scenario scenario = paper_scenario(2, 4, 5, 0);
  Measurements data = scenario.calibration;
  data.actuators.row(6).setConstant(-100.0);  // legs of negative length
  const auto problem = std::make_shared<CalibrationProblem>(scenario.model, data, scenario.nominal,
                                                            scenario.free_indices);
  const ImplicitCalibrationProblem implicit(problem);
  EXPECT_NE(implicit.start_failure().find("configuration 7: forward kinematics"), std::string::npos)
      << implicit.start_failure();
  const auto lm = SolverRegistry::global().create("lm");
  VectorXd x = problem->initial_free_parameters();
  const VectorXd start = x;
  const Summary summary = lm->solve_implicit(implicit, x, {});
  EXPECT_EQ(summary.termination, TerminationType::kFailed);
  EXPECT_NE(summary.message.find("configuration 7: forward kinematics"), std::string::npos)
      << summary.message;
  EXPECT_EQ(x, start);
  // The nested problem says the same.
  VectorXd y = start;
  const Summary nested = lm->solve(*problem, y, {});
  EXPECT_EQ(nested.termination, TerminationType::kFailed);
  EXPECT_NE(nested.message.find("configuration 7: forward kinematics"), std::string::npos);
}

// lm's trust-region schedule reaches the Schur-complement solver: a radius that opens at once
// takes fewer iterations to the same minimum from nominal (docs/benchmarks.md, where it also
// says what it costs from far starts), and a bad value is refused as in the nested solve.
TEST(ImplicitFormulation, TakesLmsTrustRegionSchedule) {
  const auto lm = SolverRegistry::global().create("lm");
  const Scenario scenario = paper_scenario(5, 1);
  const auto problem = scenario.make_problem();
  VectorXd default_x = problem->initial_free_parameters(), open_x = default_x;
  const CalibrationSolve by_default =
      solve_calibration(*lm, *problem, Prior{}, default_x, {}, Formulation::kImplicit);
  SolverOptions open;
  open.backend = lm->parse_settings({{"initial_trust_radius", "1e8"}, {"max_radius_growth", "10"}});
  const CalibrationSolve opened =
      solve_calibration(*lm, *problem, Prior{}, open_x, open, Formulation::kImplicit);
  ASSERT_EQ(opened.formulation, Formulation::kImplicit) << opened.note;
  EXPECT_TRUE(opened.summary.converged()) << opened.summary.message;
  EXPECT_LT(opened.summary.iterations, by_default.summary.iterations);
  EXPECT_LE((open_x - default_x).lpNorm<Eigen::Infinity>(), 1e-3);
  EXPECT_LE(opened.summary.final_cost, by_default.summary.final_cost * (1 + 1e-9));
  // Settings filled in code are held to the rules text is.
  LevenbergMarquardtSettings negative;
  negative.initial_trust_radius = -1;
  SolverOptions bad;
  bad.backend = std::make_shared<LevenbergMarquardtSettings>(negative);
  VectorXd x = problem->initial_free_parameters();
  EXPECT_THROW(solve_calibration(*lm, *problem, Prior{}, x, bad, Formulation::kImplicit),
               InvalidSolverOptions);
}

// Case 4 from +-20 mm, seed 95: the implicit solve stalls 2-4e-4 mm from the nested end point
// (docs/benchmarks.md, "Fourth round"). The caller gets the nested solve from the same start,
// bit for bit, and a note with the implicit solve's verdict.
TEST(ImplicitFormulation, AFailedImplicitSolveIsReplacedByTheNestedOneFromTheStart) {
  const auto lm = SolverRegistry::global().create("lm");
  const Scenario scenario = paper_scenario(4, 95, 20, 0);
  const auto problem = scenario.make_problem();
  const VectorXd start = problem->initial_free_parameters();
  {
    VectorXd x = start;
    const ImplicitCalibrationProblem implicit(problem);
    const Summary alone = lm->solve_implicit(implicit, x, {});
    ASSERT_EQ(alone.termination, TerminationType::kFailed)
        << "this start no longer makes the implicit solve fail; the test needs one that does: "
        << alone.message;
  }
  VectorXd nested_x = start, x = start;
  const CalibrationSolve nested =
      solve_calibration(*lm, *problem, Prior{}, nested_x, {}, Formulation::kNested);
  int callbacks = 0;
  SolverOptions counting;
  counting.callback = [&](const IterationRecord&, const VectorXd&) {
    ++callbacks;
    return CallbackAction::kContinue;
  };
  const CalibrationSolve solved =
      solve_calibration(*lm, *problem, Prior{}, x, counting, Formulation::kImplicit);
  EXPECT_EQ(solved.formulation, Formulation::kNested);
  ASSERT_TRUE(solved.failed_implicit.has_value());
  EXPECT_EQ(solved.failed_implicit->termination, TerminationType::kFailed);
  EXPECT_NE(
      solved.note.find("implicit formulation failed after " +
                       std::to_string(solved.failed_implicit->iterations) + " iterations (stalled"),
      std::string::npos)
      << solved.note;
  EXPECT_NE(solved.note.find("solved nested from the same start"), std::string::npos);
  // The implicit solver's own "(implicit formulation)" suffix is not repeated inside it.
  EXPECT_EQ(solved.note.find("(implicit formulation)"), std::string::npos) << solved.note;
  ASSERT_TRUE(nested.summary.converged()) << nested.summary.message;
  EXPECT_TRUE(solved.summary.converged()) << solved.summary.message;
  EXPECT_EQ(x, nested_x);
  EXPECT_EQ(solved.summary.final_cost, nested.summary.final_cost);
  EXPECT_EQ(solved.summary.iterations, nested.summary.iterations);
  // The user's callback saw both solves.
  EXPECT_EQ(callbacks,
            static_cast<int>(solved.failed_implicit->trace.size() + solved.summary.trace.size()));
  // A simulation's iteration track is the nested solve's alone.
  const CalibrationRun run =
      run_calibration(scenario, *lm, {}, /*track_iterations=*/true, Formulation::kImplicit);
  EXPECT_EQ(run.formulation, Formulation::kNested);
  EXPECT_EQ(run.trace_errors.size(), run.summary.trace.size());
  EXPECT_NE(run.formulation_note.find("solved nested from the same start"), std::string::npos);
  // Its solve time is what the calibration took: both solves, not the nested one alone.
  const CalibrationRun untracked =
      run_calibration(scenario, *lm, {}, /*track_iterations=*/false, Formulation::kImplicit);
  ASSERT_EQ(untracked.formulation, Formulation::kNested);
  EXPECT_GT(untracked.solve_seconds, untracked.summary.wall_seconds);
}

TEST(ImplicitFormulation, WhatItDoesNotHandleIsSolvedNestedWithANote) {
  const auto lm = SolverRegistry::global().create("lm");
  // An open chain.
  {
    const Scenario scenario = preset_scenario("puma560", 20, 1);
    const auto problem = scenario.make_problem();
    VectorXd x = problem->initial_free_parameters();
    const CalibrationSolve solved =
        solve_calibration(*lm, *problem, model_prior(*problem), x, {}, Formulation::kImplicit);
    EXPECT_EQ(solved.formulation, Formulation::kNested);
    EXPECT_NE(solved.note.find("not a closed chain"), std::string::npos) << solved.note;
    EXPECT_EQ(default_formulation(problem->model()), Formulation::kNested);
  }
  // A backend without it, and lm with a backend option.
  const Scenario scenario = paper_scenario(1, 1, 5, 0);
  const auto problem = scenario.make_problem();
  SolverOptions with_loss;
  with_loss.loss = RobustLoss::parse("huber:1");
  for (const auto& [name, options] :
       std::vector<std::pair<std::string, SolverOptions>>{{"gn", {}}, {"lm", with_loss}}) {
    const auto solver = SolverRegistry::global().create(name);
    VectorXd x = problem->initial_free_parameters();
    const CalibrationSolve solved =
        solve_calibration(*solver, *problem, Prior{}, x, options, Formulation::kImplicit);
    EXPECT_EQ(solved.formulation, Formulation::kNested) << name;
    EXPECT_NE(solved.note.find("does not solve it"), std::string::npos) << solved.note;
    EXPECT_TRUE(solved.summary.converged()) << solved.summary.message;
  }
  EXPECT_THROW(parse_formulation("implicitt"), std::invalid_argument);
}

}  // namespace
}  // namespace kincal
