// Multiplying every residual by one constant does not move the least-squares minimum, so it
// must not move any backend's result either (docs/solvers.md, "Scale"). It did (issue 35): a
// model's reading_std of 1e8 divides every residual by 1e8 and the cost by 1e16, and the
// absolute gradient test (max|J^T r| <= 1e-12) fired at the start or after a few iterations on
// every backend, millimetres from the minimum; Ceres' own gradient test, and Ipopt's, are
// absolute too. Every backend of the registry solves the same noisy hexapod calibration with
// its residuals multiplied by 2^-27 (~7e-9) and 2^27 (~1e8) (problems/ScaledProblem) and must
// end where it ends at scale 1, with the same verdict after as many iterations. Powers of two
// scale exactly, and every backend's decisions are now invariant to the scale, so they take the
// same steps (to rounding) and stop at the same point (kincal calibrate with the audit's
// decimal factors, where rounding may move a stop by an iteration: tests/cli/audit3/numerics.sh).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/problems/scaled_problem.hpp"
#include "kincal/problems/solver_contract.hpp"
#include "solver_fixtures.hpp"

namespace kincal {
namespace {

using kincal::testing::backend_test_name;
using kincal::testing::every_backend;
using kincal::testing::paper_scenario;
using kincal::testing::why_not_built;

bool is_least_squares(const std::string& name) {
  const std::string family = name.substr(0, name.find(':'));
  for (const auto& info : SolverRegistry::global().list())
    if (info.name == name || info.name == family + ":<ALGORITHM>")
      return info.kind == SolverKind::kLeastSquares;
  return false;
}

// The cube hexapod with two free parameters: small enough for every NLopt algorithm,
// derivative-free ones included, to reach its minimum.
std::shared_ptr<MeasurementModel> two_free_hexapod() {
  auto model = make_cube_hexapod();
  model->parameters().set_free("*", false);
  for (const char* name : {"leg4.base.x", "leg5.platform.y"})
    model->parameters().set_free(name, true);
  return model;
}

// The paper's noisy case 3 (seed 5): every parameter for the least-squares backends, two for
// the general minimisers (as the conformance suite gives them).
Scenario scenario_for(const std::string& solver) {
  return paper_scenario(is_least_squares(solver) ? make_cube_hexapod() : two_free_hexapod(), 3, 5,
                        5, 0);
}

SolverOptions options_for(const std::string& solver) {
  SolverOptions options;
  if (solver.rfind("nlopt:", 0) == 0) options.max_iterations = 4000;  // evaluations
  if (solver.rfind("nlopt:LN_", 0) == 0)
    options.backend =
        SolverRegistry::global().create(solver)->parse_settings({{"initial_step", "1"}});  // mm
  return options;
}

const double kScales[] = {std::ldexp(1.0, -27), std::ldexp(1.0, 27)};

std::string huber(double delta) {
  char text[64];
  std::snprintf(text, sizeof text, "huber:%.17g", delta);
  return text;
}

class ResidualScale : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    const std::string why = why_not_built(GetParam());
    if (!why.empty()) GTEST_SKIP() << why;
  }
  // Solves `problem` from `start` at scale 1 and at kScales, with `options` and, at scale s,
  // `scaled_options(s)`; expects the same end.
  // With a robust loss the contract's checker does not apply (it measures 1/2 |r|^2).
  void expect_invariant(const LeastSquaresProblem& problem, const VectorXd& start,
                        const SolverOptions& options,
                        const std::function<SolverOptions(double)>& scaled_options,
                        bool check_contract = true) {
    const auto solver = SolverRegistry::global().create(GetParam());
    VectorXd reference = start;
    const Summary at_one = solver->solve(problem, reference, options);
    // The solve moved: the noisy minimum is millimetres from nominal.
    ASSERT_GT((reference - start).lpNorm<Eigen::Infinity>(), 0.1) << at_one.brief_report();
    for (double scale : kScales) {
      const problems::ScaledProblem scaled(problem, scale);
      const problems::CheckedSolve run =
          problems::solve_and_check(*solver, scaled, start, scaled_options(scale));
      SCOPED_TRACE("residuals times " + std::to_string(scale) + ": " + run.summary.brief_report() +
                   "\n  at scale 1: " + at_one.brief_report());
      EXPECT_EQ(run.summary.termination, at_one.termination);
      EXPECT_EQ(run.summary.iterations, at_one.iterations);
      if (check_contract) {
        EXPECT_TRUE(run.contract.ok()) << run.contract.report();
      }
      // The same point: powers of two scale exactly, so only a decision that depends on the
      // scale could move it (the data determine these parameters to ~1 mm; a stop one
      // iteration earlier or later moves them by up to 1e-4 mm). The cost to its rounding
      // error, ~1e-9 of it here (Ipopt's steps differ from scale to scale at that level).
      EXPECT_LT((run.x - reference).lpNorm<Eigen::Infinity>(), 1e-9)
          << (run.x - reference).lpNorm<Eigen::Infinity>();
      EXPECT_NEAR(run.summary.final_cost, scale * scale * at_one.final_cost,
                  1e-9 * scale * scale * at_one.final_cost);
    }
  }
};

TEST_P(ResidualScale, ACommonScaleOfTheResidualsChangesNothing) {
  const Scenario scenario = scenario_for(GetParam());
  const auto problem = scenario.make_problem();
  const SolverOptions options = options_for(GetParam());
  expect_invariant(*problem, problem->initial_free_parameters(), options,
                   [&](double) { return options; });
}

// A robust loss multiplies the cost by its delta where the residuals are far beyond it: with
// huber:1e-20 the cost is ~1e-20 |r|_1 and every backend stopped at the start ("converged
// after 0 iterations", issue 35). Scaling the residuals and delta together changes nothing; a
// delta far below every residual is the L1 fit, which the backends approach slowly (they may
// end at their iteration limit), but never by stopping where they started.
TEST_P(ResidualScale, ARobustLossIsScaledWithTheResiduals) {
  const auto solver = SolverRegistry::global().create(GetParam());
  if (!solver->takes_robust_loss()) GTEST_SKIP() << GetParam() << " takes no robust loss";
  const Scenario scenario = scenario_for(GetParam());
  const auto problem = scenario.make_problem();
  for (const double delta : {1e-2, 1e-20}) {
    SCOPED_TRACE(huber(delta));
    SolverOptions options = options_for(GetParam());
    options.loss = RobustLoss::parse(huber(delta));
    expect_invariant(
        *problem, problem->initial_free_parameters(), options,
        [&](double scale) {
          SolverOptions scaled = options;
          scaled.loss = RobustLoss::parse(huber(delta * scale));
          return scaled;
        },
        false);
  }
}

INSTANTIATE_TEST_SUITE_P(EveryBackend, ResidualScale, ::testing::ValuesIn(every_backend()),
                         backend_test_name);

}  // namespace
}  // namespace kincal
