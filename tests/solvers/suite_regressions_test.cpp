// What the MGH suite taught the backends, one behaviour per test: each of these failed before
// the fixes of issue 11 or, for uphill steps, issue 24 (docs/solvers.md).

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/problems/mgh_problems.hpp"
#include "kincal/problems/solver_contract.hpp"
#include "kincal/problems/suite.hpp"
#include "solver_fixtures.hpp"

namespace kincal {
namespace {

using problems::CheckedSolve;

VectorXd start(const problems::TestProblem& p, const std::string& label) {
  for (const auto& s : problems::suite_starts(p))
    if (s.label == label) return s.x;
  throw std::logic_error("no start " + label);
}

CheckedSolve run(const std::string& solver, const std::string& problem, const std::string& label,
                 const SolverOptions& options = {}) {
  const auto p = problems::select_problems(problem).at(0);
  return problems::solve_and_check(*SolverRegistry::global().create(solver), *p, start(*p, label),
                                   options);
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// lm's runaway guard, a fixed distance from the start, stopped this solve after two
// iterations: Brown's badly scaled minimum lies 1e6 from its start. Off by default now.
TEST(LmOnTheSuite, ReachesAMinimumAMillionUnitsFromTheStart) {
  const CheckedSolve r = run("lm", "mgh04_brown_badly_scaled", "x0");
  EXPECT_TRUE(r.summary.converged()) << r.summary.brief_report();
  EXPECT_LT(r.summary.final_cost, 1e-10);
  EXPECT_TRUE(r.contract.ok()) << r.contract.report();
  const auto lm = SolverRegistry::global().create("lm");
  SolverOptions guarded;
  guarded.backend = lm->parse_settings({{"runaway_factor", "1e3"}});
  const CheckedSolve g = run("lm", "mgh04_brown_badly_scaled", "x0", guarded);
  EXPECT_EQ(g.summary.termination, TerminationType::kDiverged) << g.summary.brief_report();
  EXPECT_TRUE(contains(g.summary.message, "ran away")) << g.summary.message;
  guarded.backend = lm->parse_settings({{"runaway_factor", "none"}});
  EXPECT_NO_THROW(lm->check_options(guarded));
}

// From 100 x0 the product residual's derivatives fall from 2e15 to 3e5 on the way; with the
// running maximum as its Marquardt scale lm crawled (|dx| ~ 0.004 per iteration at the largest
// trust radius). Stale scales are now reset.
TEST(LmOnTheSuite, ResetsStaleScalesAndReachesTheMinimum) {
  const CheckedSolve r = run("lm", "mgh27_brown_almost_linear_n10", "100x0");
  EXPECT_TRUE(r.summary.converged()) << r.summary.brief_report();
  EXPECT_LT(r.summary.final_cost, 1e-10);
  EXPECT_LE(r.summary.iterations, 200);
}

// lm's last step after its predicted-decrease test fired was taken with residuals only, and
// the verdict stayed the one judged before it. With these trust-region settings that step
// leaves Biggs EXP6 (from 100 x0) for a point that passes none of the three tests, and the
// claim "converged" outlived it. The verdict is now judged where the step ends.
TEST(LmOnTheSuite, TheLastStepIsJudgedWhereItEnds) {
  SolverOptions options;
  options.backend = SolverRegistry::global().create("lm")->parse_settings(
      {{"initial_trust_radius", "1e5"}, {"max_radius_growth", "30"}});
  const CheckedSolve r = run("lm", "mgh18_biggs_exp6", "100x0", options);
  EXPECT_TRUE(r.contract.ok()) << r.contract.report() << "\n" << r.summary.brief_report();
}

// Gulf from 100 x0: every exponential underflows, the Jacobian is zero, the gradient test
// fires at once. That is no minimum.
TEST(LmOnTheSuite, AZeroJacobianIsAPlateauNotConvergence) {
  const CheckedSolve r = run("lm", "mgh11_gulf", "100x0");
  EXPECT_EQ(r.summary.termination, TerminationType::kFailed) << r.summary.brief_report();
  EXPECT_TRUE(contains(r.summary.message, "plateau")) << r.summary.message;
  EXPECT_TRUE(r.contract.ok()) << r.contract.report();
}

// Bard from 100 x0 runs off towards the published minimum at infinity (x2, x3 -> -inf): the
// claim is true there, and names the asymptote.
TEST(LmOnTheSuite, AnAsymptoteIsNamed) {
  const CheckedSolve r = run("lm", "mgh08_bard", "100x0");
  const auto bard = problems::select_problems("mgh08_bard").at(0);
  EXPECT_TRUE(r.summary.converged()) << r.summary.brief_report();
  EXPECT_TRUE(contains(r.summary.message, "plateau")) << r.summary.message;
  EXPECT_EQ(problems::classify(*bard, r.summary.final_cost), problems::Outcome::kPublishedLocal);
  EXPECT_TRUE(r.contract.ok()) << r.contract.report();
}

// Osborne 1 from 100 x0: the iterates must follow a long curved valley, and every step that
// kept going the same way raised the cost a little before the next one lowered it. Without
// uphill steps lm bounced across the valley until the iteration limit; with them (the
// default) it reaches the published minimum, and each uphill iterate kept the previous
// step's direction and the cap on its cost (Transtrum & Sethna's criterion, checked here
// from the iterates the callback sees).
TEST(LmOnTheSuite, UphillStepsFollowACurvedValley) {
  const auto osborne = problems::select_problems("mgh17_osborne_1").at(0);
  SolverOptions options;
  std::vector<VectorXd> iterates;
  options.callback = [&](const IterationRecord&, const VectorXd& x) {
    iterates.push_back(x);
    return CallbackAction::kContinue;
  };
  const CheckedSolve r = run("lm", "mgh17_osborne_1", "100x0", options);
  EXPECT_TRUE(r.summary.converged()) << r.summary.brief_report();
  EXPECT_EQ(problems::classify(*osborne, r.summary.final_cost),
            problems::Outcome::kPublishedMinimum)
      << r.summary.brief_report();
  EXPECT_TRUE(r.contract.ok()) << r.contract.report();

  const auto& trace = r.summary.trace;
  ASSERT_EQ(trace.size(), iterates.size());
  int uphill = 0;
  double lowest = trace[0].cost;
  for (std::size_t k = 2; k < trace.size(); ++k) {
    lowest = std::min(lowest, trace[k - 1].cost);
    if (trace[k].cost <= trace[k - 1].cost) continue;
    ++uphill;
    const VectorXd step = iterates[k] - iterates[k - 1];
    const VectorXd previous = iterates[k - 1] - iterates[k - 2];
    const double beta = step.dot(previous) / (step.norm() * previous.norm());
    // The best point evaluated (probes and trials included) is no higher than `lowest`.
    EXPECT_LE((1 - beta) * (1 - beta) * trace[k].cost, lowest) << "iterate " << k;
    EXPECT_LE(trace[k].cost, 2 * lowest) << "iterate " << k;
  }
  EXPECT_GT(uphill, 0);

  SolverOptions downhill_only;
  downhill_only.backend =
      SolverRegistry::global().create("lm")->parse_settings({{"uphill_steps", "false"}});
  const CheckedSolve d = run("lm", "mgh17_osborne_1", "100x0", downhill_only);
  EXPECT_NE(problems::classify(*osborne, d.summary.final_cost),
            problems::Outcome::kPublishedMinimum)
      << d.summary.brief_report();
  for (std::size_t k = 1; k < d.summary.trace.size(); ++k)
    EXPECT_LE(d.summary.trace[k].cost, d.summary.trace[k - 1].cost) << "iterate " << k;
  EXPECT_TRUE(d.contract.ok()) << d.contract.report();
}

// gn's undamped steps may go uphill; a test that fires at a later, costlier iterate says
// nothing about the best point, which is what gn returns. It used to report `converged`.
TEST(GnOnTheSuite, ATestFiringAtACostlierIterateIsNotConvergenceOfTheBestPoint) {
  const CheckedSolve r = run("gn", "mgh09_gaussian", "10x0");
  EXPECT_TRUE(kincal::testing::stalled(r.summary)) << r.summary.brief_report();
  EXPECT_TRUE(r.contract.ok()) << r.contract.report();
}

class IpoptOnTheSuite : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string why = kincal::testing::why_not_built("ipopt");
    if (!why.empty()) GTEST_SKIP() << why;
  }
};

// Meyer from 100 x0: Ipopt moved where the model is flat in every parameter and reported
// success after one iteration, at 4.4e7 times the published minimum.
TEST_F(IpoptOnTheSuite, ASuccessOnAZeroJacobianIsAPlateau) {
  const CheckedSolve r = run("ipopt", "mgh10_meyer", "100x0");
  EXPECT_NE(r.summary.termination, TerminationType::kConverged) << r.summary.brief_report();
  EXPECT_TRUE(contains(r.summary.message, "plateau")) << r.summary.message;
  EXPECT_TRUE(r.contract.ok()) << r.contract.report();
}

// Biggs EXP6 from x0: a failed step computation used to return a point costing 1.7e299 from a
// start of cost 0.39. The best point is returned now, whatever Ipopt ends on.
TEST_F(IpoptOnTheSuite, ReturnsTheBestPointWhateverItEndsOn) {
  const CheckedSolve r = run("ipopt", "mgh18_biggs_exp6", "x0");
  EXPECT_LE(r.summary.final_cost, r.summary.initial_cost) << r.summary.brief_report();
  EXPECT_TRUE(r.contract.ok()) << r.contract.report();
}

// Penalty function I (n = 10): Ipopt's acceptable-level stop compares the cost change with
// max(1, |f|), an absolute test at f = 3.5e-5; it stopped where the Gauss-Newton model still
// promised 1e-9 of the cost. It now goes on from there until our test holds.
TEST_F(IpoptOnTheSuite, AnAcceptableLevelStopShortOfOurTestIsContinued) {
  const CheckedSolve r = run("ipopt", "mgh23_penalty_1_n10", "x0");
  EXPECT_TRUE(r.summary.converged()) << r.summary.brief_report();
  EXPECT_TRUE(r.contract.ok()) << r.contract.report();
}

}  // namespace
}  // namespace kincal
