// The conformance suite: every featured backend of the registry
// (SolverRegistry::global().featured_names(): gn, lm, and ceres, nlopt:<ALGORITHM>, ipopt
// when built) runs the same checks. A backend whose CMake option is OFF is simply not in the
// registry, so it is not instantiated here; tests that name one skip with a reason.
//
// Tolerances per backend family (on every free parameter, mm, noise-free data):
//   exact       gn, lm, ceres, ipopt (and any future backend): 1e-6, the full 24-parameter
//               case 1 from nominal, default options.
//   nlopt:LD_*  gradient-based NLopt (L-BFGS, SLSQP, ...): first-order and quasi-Newton
//               methods on a Hessian with condition number ~1e10 cannot pin the flat
//               directions (L-BFGS stops ~0.5 mm off with the cost down 3e11-fold), so the
//               full case 1 with up to 20000 evaluations must come within 1 mm on every
//               parameter *and* bring the cost down by 9 orders of magnitude.
//   nlopt:LN_*  derivative-free NLopt: the same case 1 data with 2 free parameters (the
//               others fixed at their true values), initial_step = 1 mm, up to 4000
//               evaluations, within 1e-3 mm. (With 4 free parameters BOBYQA, Nelder-Mead
//               and Sbplx still reach 1e-7 mm but COBYLA stalls ~0.6 mm off.)
//   nlopt:LD_MMA  a documented exception: Svanberg's MMA builds conservative separable
//               convex approximations, which crawl along this problem's ill-conditioned
//               valleys; measured on case 1 it is still 4-10 mm off after 20000 evaluations,
//               with or without bounds or Jacobian scaling, and it sometimes proposes a
//               non-finite point. It is held to what it can honestly do: a 1e4-fold cost
//               decrease within 3000 evaluations, and no claim of convergence unless it is
//               within the gradient-based 1 mm bound. See docs/solvers.md.

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>

#include "framework/simulation.hpp"
#include "framework/solver_registry.hpp"
#include "models/presets.hpp"

namespace kincal {
namespace {

enum class Family { kExact, kNloptGradient, kNloptDerivativeFree, kNloptMma };

Family family_of(const std::string& name) {
  if (name == "nlopt:LD_MMA") return Family::kNloptMma;
  if (name.rfind("nlopt:LN_", 0) == 0) return Family::kNloptDerivativeFree;
  if (name.rfind("nlopt:", 0) == 0) return Family::kNloptGradient;
  return Family::kExact;
}

// Case 1 of the paper (noise-free), one fixed seed.
const Scenario& full_case1() {
  static const Scenario scenario = [] {
    ScenarioOptions options;
    options.num_configurations = paper_case(1).num_configurations;
    options.num_validation = 0;
    options.seed = 11;
    return make_scenario(make_cube_hexapod(), options);
  }();
  return scenario;
}

// The same kind of data with only two free parameters, for derivative-free methods.
const Scenario& small_case1() {
  static const Scenario scenario = [] {
    auto model = make_cube_hexapod();
    model->parameters().set_free("*", false);
    for (const char* name : {"leg4.base.x", "leg5.platform.y"})
      model->parameters().set_free(name, true);
    ScenarioOptions options;
    options.num_configurations = paper_case(1).num_configurations;
    options.num_validation = 0;
    options.seed = 11;
    return make_scenario(model, options);
  }();
  return scenario;
}

const Scenario& scenario_for(Family family) {
  return family == Family::kNloptDerivativeFree ? small_case1() : full_case1();
}

double max_parameter_error(const Scenario& scenario, const VectorXd& estimate) {
  double worst = 0;
  for (int i : scenario.free_indices)
    worst = std::max(worst, std::abs(estimate[i] - scenario.truth[i]));
  return worst;
}

// Residuals that can never be computed, like forward kinematics failing everywhere.
class UncomputableProblem : public LeastSquaresProblem {
 public:
  int num_parameters() const override { return 3; }
  int num_residual_blocks() const override { return 5; }
  int residuals_per_block() const override { return 1; }
  bool evaluate_block(int, const VectorXd&, Eigen::Ref<VectorXd>, Eigen::Ref<MatrixXd>*,
                      std::string* why) const override {
    if (why) *why = "forward kinematics failed (test problem)";
    return false;
  }
};

class Conformance : public ::testing::TestWithParam<std::string> {
 protected:
  std::unique_ptr<Solver> solver() const { return SolverRegistry::global().create(GetParam()); }
  Family family() const { return family_of(GetParam()); }
};

// (a) Noise-free data from nominal reaches the true parameters.
TEST_P(Conformance, NoiseFreeCase1ReachesTheTruth) {
  const Scenario& scenario = scenario_for(family());
  SolverOptions options;
  double tolerance = 1e-6;
  if (family() == Family::kNloptGradient) {
    options.max_iterations = 20000;
    tolerance = 1.0;
  } else if (family() == Family::kNloptDerivativeFree) {
    options.max_iterations = 4000;
    options.backend_options["initial_step"] = "1";  // mm; NLopt's default is far too large
    tolerance = 1e-3;
  }
  if (family() == Family::kNloptMma) {
    options.max_iterations = 3000;
    const CalibrationRun run = run_calibration(scenario, *solver(), options, false);
    const Summary& summary = run.summary;
    EXPECT_LT(summary.final_cost, 1e-4 * summary.initial_cost) << summary.brief_report();
    if (summary.termination == TerminationType::kConverged) {
      EXPECT_LT(max_parameter_error(scenario, run.estimate), 1.0) << summary.brief_report();
    }
    EXPECT_FALSE(summary.message.empty());
    EXPECT_GT(summary.residual_evaluations, 0);
    return;
  }
  const CalibrationRun run = run_calibration(scenario, *solver(), options, false);
  const Summary& summary = run.summary;
  EXPECT_EQ(summary.solver, GetParam());
  EXPECT_TRUE(
      summary.termination == TerminationType::kConverged ||
      (family() != Family::kExact && summary.termination == TerminationType::kMaxIterations))
      << summary.brief_report();
  EXPECT_LT(max_parameter_error(scenario, run.estimate), tolerance) << summary.brief_report();
  EXPECT_LE(summary.final_cost, summary.initial_cost);
  if (family() == Family::kNloptGradient) {
    EXPECT_LT(summary.final_cost, 1e-9 * summary.initial_cost) << summary.brief_report();
  }
  EXPECT_GT(summary.residual_evaluations, 0);
  EXPECT_GE(summary.wall_seconds, 0);
}

// (c) The iteration limit is reported as such.
TEST_P(Conformance, IterationLimitIsReported) {
  const Scenario& scenario = scenario_for(family());
  SolverOptions options;
  options.max_iterations = 2;
  const CalibrationRun run = run_calibration(scenario, *solver(), options, false);
  EXPECT_EQ(run.summary.termination, TerminationType::kMaxIterations) << run.summary.brief_report();
  EXPECT_FALSE(run.summary.message.empty());
  EXPECT_TRUE(run.estimate.allFinite());
  EXPECT_LE(run.summary.final_cost, run.summary.initial_cost);
}

// (c) Residuals that cannot be computed at the start end `failed`, with the reason.
TEST_P(Conformance, UncomputableResidualsFailCleanly) {
  UncomputableProblem problem;
  VectorXd x = VectorXd::Ones(3);
  const Summary summary = solver()->solve(problem, x, SolverOptions{});
  EXPECT_EQ(summary.termination, TerminationType::kFailed) << summary.brief_report();
  EXPECT_FALSE(summary.message.empty());
  EXPECT_EQ(x.size(), 3);
}

// (c) The same through a real calibration problem: leg lengths no hexapod can reach.
TEST_P(Conformance, UnreachableConfigurationsFailCleanly) {
  const Scenario& scenario = scenario_for(family());
  Measurements data = scenario.calibration;
  data.actuators.row(0).setConstant(-100.0);  // negative leg lengths
  CalibrationProblem problem(scenario.model, data, scenario.nominal, scenario.free_indices);
  VectorXd x = problem.initial_free_parameters();
  std::string why;
  ASSERT_FALSE(std::isfinite(problem.cost(x, &why)))
      << "the model computed residuals for negative leg lengths";
  const Summary summary = solver()->solve(problem, x, SolverOptions{});
  EXPECT_EQ(summary.termination, TerminationType::kFailed) << summary.brief_report();
  EXPECT_FALSE(summary.message.empty());
}

// (d) Unknown backend options are rejected before any work.
TEST_P(Conformance, UnknownBackendOptionIsRejected) {
  SolverOptions options;
  options.backend_options["surely_not_an_option"] = "1";
  EXPECT_THROW(solver()->check_options(options), InvalidSolverOptions);
  const Scenario& scenario = scenario_for(family());
  const auto problem = scenario.make_problem();
  VectorXd x = problem->initial_free_parameters();
  EXPECT_THROW(solver()->solve(*problem, x, options), InvalidSolverOptions);
}

// (d) Bounds that do not fit the problem, or cross, are rejected before any work.
TEST_P(Conformance, MisfittingBoundsAreRejected) {
  const auto problem = scenario_for(family()).make_problem();
  VectorXd x = problem->initial_free_parameters();
  SolverOptions options;
  options.lower_bounds = VectorXd::Constant(x.size() + 1, -1e3);
  options.upper_bounds = VectorXd::Constant(x.size() + 1, 1e3);
  EXPECT_THROW(solver()->solve(*problem, x, options), InvalidSolverOptions);
  options.lower_bounds = x.array() + 1.0;  // lower above upper
  options.upper_bounds = x.array() - 1.0;
  EXPECT_THROW(solver()->solve(*problem, x, options), InvalidSolverOptions);
}

// (e) The trace matches the callback, starts at iteration 0, and kStop stops.
TEST_P(Conformance, CallbackAndTraceAgree) {
  const Scenario& scenario = scenario_for(family());
  SolverOptions options;
  options.max_iterations = family() == Family::kExact ? 100 : 2000;
  int calls = 0;
  options.callback = [&](const IterationRecord&, const VectorXd& x) {
    ++calls;
    EXPECT_EQ(x.size(), static_cast<Eigen::Index>(scenario.free_indices.size()));
    return CallbackAction::kContinue;
  };
  const CalibrationRun run = run_calibration(scenario, *solver(), options, false);
  ASSERT_FALSE(run.summary.trace.empty()) << run.summary.brief_report();
  EXPECT_EQ(static_cast<int>(run.summary.trace.size()), calls);
  EXPECT_EQ(run.summary.trace[0].iteration, 0);
  EXPECT_DOUBLE_EQ(run.summary.trace[0].cost, run.summary.initial_cost);
}

TEST_P(Conformance, CallbackCanStopTheSolve) {
  const Scenario& scenario = scenario_for(family());
  SolverOptions options;
  options.max_iterations = family() == Family::kExact ? 100 : 2000;
  int calls = 0;
  options.callback = [&](const IterationRecord&, const VectorXd&) {
    return ++calls == 2 ? CallbackAction::kStop : CallbackAction::kContinue;
  };
  const CalibrationRun run = run_calibration(scenario, *solver(), options, false);
  EXPECT_EQ(run.summary.termination, TerminationType::kUserStopped) << run.summary.brief_report();
  EXPECT_EQ(calls, 2);
  EXPECT_EQ(static_cast<int>(run.summary.trace.size()), calls);
  EXPECT_TRUE(run.estimate.allFinite());
}

INSTANTIATE_TEST_SUITE_P(EveryBackend, Conformance,
                         ::testing::ValuesIn(SolverRegistry::global().featured_names()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

// (b) A noisy case: lm, ceres and ipopt reach the same minimum, parameters within 1e-6 mm.
class SameNoisyMinimum : public ::testing::TestWithParam<std::string> {};

TEST_P(SameNoisyMinimum, AgreesWithLm) {
  const auto& registry = SolverRegistry::global();
  if (!registry.contains(GetParam()))
    GTEST_SKIP() << GetParam() << " is not built (its KINCAL_WITH_ option is OFF)";
  ScenarioOptions scenario_options;
  scenario_options.num_configurations = paper_case(3).num_configurations;
  scenario_options.noise_half_width = paper_case(3).noise_half_width;
  scenario_options.num_validation = 0;
  scenario_options.seed = 5;
  const Scenario scenario = make_scenario(make_cube_hexapod(), scenario_options);
  // Tight tolerances: the valley is so flat (cond(J) ~ 1e5) that 1e-6 mm in the parameters
  // is a relative cost change of ~1e-15.
  SolverOptions options;
  options.max_iterations = 500;
  options.function_tolerance = 1e-16;
  options.parameter_tolerance = 1e-14;
  options.gradient_tolerance = 1e-13;
  const CalibrationRun reference =
      run_calibration(scenario, *registry.create("lm"), options, false);
  ASSERT_TRUE(reference.summary.converged()) << reference.summary.brief_report();
  const CalibrationRun run =
      run_calibration(scenario, *registry.create(GetParam()), options, false);
  EXPECT_NE(run.summary.termination, TerminationType::kFailed) << run.summary.brief_report();
  EXPECT_NE(run.summary.termination, TerminationType::kDiverged) << run.summary.brief_report();
  double worst = 0;
  for (int i : scenario.free_indices)
    worst = std::max(worst, std::abs(run.estimate[i] - reference.estimate[i]));
  EXPECT_LT(worst, 1e-6) << run.summary.brief_report()
                         << "\nlm: " << reference.summary.brief_report();
}

INSTANTIATE_TEST_SUITE_P(Backends, SameNoisyMinimum, ::testing::Values("ceres", "ipopt"));

// (d) Unknown solver names are rejected by the registry.
TEST(ConformanceRegistry, UnknownSolverNameIsRejected) {
  const auto& registry = SolverRegistry::global();
  EXPECT_THROW(registry.create("no-such-solver"), InvalidSolverOptions);
  EXPECT_THROW(registry.create(""), InvalidSolverOptions);
  EXPECT_FALSE(registry.contains("no-such-solver"));
  try {
    registry.create("no-such-solver");
  } catch (const InvalidSolverOptions& e) {
    EXPECT_NE(std::string(e.what()).find("lm"), std::string::npos)
        << "the error should list what is available: " << e.what();
  }
  if (registry.contains("nlopt:LD_LBFGS")) {
    EXPECT_THROW(registry.create("nlopt:NOT_AN_ALGORITHM"), InvalidSolverOptions);
  }
}

TEST(ConformanceRegistry, EveryFeaturedNameCanBeCreated) {
  const auto names = SolverRegistry::global().featured_names();
  EXPECT_NE(std::find(names.begin(), names.end(), "gn"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "lm"), names.end());
  for (const auto& name : names) {
    const auto solver = SolverRegistry::global().create(name);
    ASSERT_NE(solver, nullptr) << name;
    EXPECT_EQ(solver->name(), name);
  }
}

}  // namespace
}  // namespace kincal
