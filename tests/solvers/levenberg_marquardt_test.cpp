// `lm` on the paper's cases and on small generic problems: convergence, robust losses,
// bounds, failing evaluations, option validation. That its loop does not allocate is tested
// in tests/allocation/ (a binary that replaces malloc, which sanitizers cannot share).

#include <gtest/gtest.h>

#include <cmath>

#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/presets.hpp"
#include "kincal/solvers/levenberg_marquardt.hpp"
#include "solver_fixtures.hpp"

namespace kincal {
namespace {

using kincal::testing::paper_scenario;

std::unique_ptr<Solver> lm() { return SolverRegistry::global().create("lm"); }

// y = a exp(-b t) + c sampled at 20 points: a small, allocation-free generic problem.
class ExponentialFit : public LeastSquaresProblem {
 public:
  ExponentialFit() {
    for (int i = 0; i < kPoints; ++i) {
      t_[i] = 0.25 * i;
      y_[i] = 3.0 * std::exp(-0.7 * t_[i]) + 0.5 + 1e-3 * std::sin(7.0 * i);  // small misfit
    }
  }
  int num_parameters() const override { return 3; }
  int num_residual_blocks() const override { return kPoints; }
  int residuals_per_block() const override { return 1; }
  bool evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                      Eigen::Ref<MatrixXd>* jacobian, std::string*) const override {
    const double e = std::exp(-x[1] * t_[block]);
    residuals[0] = x[0] * e + x[2] - y_[block];
    if (jacobian) (*jacobian) << e, -x[0] * t_[block] * e, 1.0;
    return true;
  }

 private:
  static constexpr int kPoints = 20;
  double t_[kPoints], y_[kPoints];
};

// r = x^2 - 2, whose residual cannot be computed beyond x = 1.5 (a stand-in for forward
// kinematics failing), or anywhere but at the start when `only_start` is set.
class FragileRoot : public LeastSquaresProblem {
 public:
  explicit FragileRoot(bool only_start = false) : only_start_(only_start) {}
  int num_parameters() const override { return 1; }
  int num_residual_blocks() const override { return 1; }
  int residuals_per_block() const override { return 1; }
  bool evaluate_block(int, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                      Eigen::Ref<MatrixXd>* jacobian, std::string* why) const override {
    if (x[0] > 1.5 || (only_start_ && x[0] != 0.5)) {
      if (why) *why = "outside the valid region";
      return false;
    }
    residuals[0] = x[0] * x[0] - 2.0;
    if (jacobian) (*jacobian)(0, 0) = 2.0 * x[0];
    return true;
  }

 private:
  bool only_start_;
};

// ---- the paper's cases -------------------------------------------------------------------

struct CaseAndSeed {
  int case_id;
  std::uint64_t seed;
};

class PaperCases : public ::testing::TestWithParam<CaseAndSeed> {};

TEST_P(PaperCases, ConvergesToTheLeastSquaresMinimum) {
  const auto [case_id, seed] = GetParam();
  const Scenario scenario = paper_scenario(case_id, seed);
  SolverOptions options;
  const CalibrationRun run = run_calibration(scenario, *lm(), options, false);
  ASSERT_EQ(run.summary.termination, TerminationType::kConverged) << run.summary.brief_report();
  EXPECT_LT(run.summary.final_cost, run.summary.initial_cost);
  if (paper_case(case_id).noise_half_width == 0) {
    for (int i : scenario.free_indices)
      EXPECT_NEAR(run.estimate[i], scenario.truth[i], 1e-6) << scenario.model->parameters()[i].name;
    EXPECT_LT(run.after.position_max_mm, 1e-6);
  } else {
    // A minimum: the gradient vanishes relative to the starting one, and the cost is no
    // higher than where a long Gauss-Newton run settles. (With this much noise the minimum
    // itself can be a worse model than nominal: the problem, not the solver; see theory.md.)
    ASSERT_FALSE(run.summary.trace.empty());
    EXPECT_LT(run.summary.trace.back().gradient_norm, 1e-6 * run.summary.trace[0].gradient_norm)
        << run.summary.brief_report();
    SolverOptions long_run;
    long_run.max_iterations = 300;
    const CalibrationRun gn =
        run_calibration(scenario, *SolverRegistry::global().create("gn"), long_run, false);
    if (gn.summary.converged()) {
      EXPECT_LE(run.summary.final_cost, gn.summary.final_cost * (1 + 1e-9));
    }
  }
}

std::vector<CaseAndSeed> all_cases_several_seeds() {
  std::vector<CaseAndSeed> out;
  for (int c = 1; c <= 5; ++c)
    for (std::uint64_t seed = 1; seed <= 4; ++seed) out.push_back({c, seed});
  // The slowest seed of cases 1-5 in 1..50: a long curved valley that takes lm ~100
  // iterations (gn and ceres do not reach the minimum in 100), within the default limit.
  out.push_back({4, 49});
  return out;
}

INSTANTIATE_TEST_SUITE_P(AllCases, PaperCases, ::testing::ValuesIn(all_cases_several_seeds()),
                         [](const ::testing::TestParamInfo<CaseAndSeed>& info) {
                           return "case" + std::to_string(info.param.case_id) + "_seed" +
                                  std::to_string(info.param.seed);
                         });

TEST(LevenbergMarquardt, RecoversTwentyMillimetreParameterErrors) {
  // Four times the paper's parameter errors; plain gn fails on most of these.
  for (std::uint64_t seed : {1, 2, 3, 4}) {
    const Scenario scenario = paper_scenario(1, seed, 20);
    const CalibrationRun run = run_calibration(scenario, *lm(), SolverOptions{}, false);
    EXPECT_TRUE(run.summary.converged()) << run.summary.brief_report();
    EXPECT_LT(run.parameter_rms_error, 1e-6) << "seed " << seed;
  }
}

// Noise-free case 1 reaches a zero-residual minimum where, at cost ~1e-21, trials are rejected
// by rounding noise. An uphill step taken there (trial 41 of `kincal reproduce`) left lm at
// a point that fails its own test, a stall; uphill steps are now kept out of that end game.
TEST(LevenbergMarquardt, TakesNoUphillStepInTheRoundingNoiseOfAZeroResidualMinimum) {
  const Scenario scenario = paper_scenario(1, 17268152288442623880ULL);
  const CalibrationRun run = run_calibration(scenario, *lm(), SolverOptions{}, false);
  EXPECT_TRUE(run.summary.converged()) << run.summary.brief_report();
  EXPECT_LT(run.parameter_rms_error, 1e-6);
  for (std::size_t k = 1; k < run.summary.trace.size(); ++k)
    if (run.summary.trace[k].cost < 1e-15) {
      EXPECT_LE(run.summary.trace[k].cost, run.summary.trace[k - 1].cost) << "iterate " << k;
    }
}

// Geodesic acceleration costs a residual evaluation per trial (its probe). In the end game
// of a noisy case, where the model promises less than 1e-6 of the cost, the correction is
// negligible and the probe is skipped: before, every trial but the closing one had a probe
// (probes = iterations - 1 on these seeds); on the way down they still do.
TEST(LevenbergMarquardt, TakesNoGeodesicProbeInTheEndGame) {
  for (std::uint64_t seed : {1, 2, 3, 4}) {
    const CalibrationRun run =
        run_calibration(paper_scenario(5, seed), *lm(), SolverOptions{}, false);
    const Summary& s = run.summary;
    ASSERT_TRUE(s.converged()) << s.brief_report();
    // The residual-only evaluations are the probes (every trial is evaluated with its
    // Jacobian, as are the start and the closing step).
    const int probes = s.residual_evaluations - s.jacobian_evaluations;
    EXPECT_LE(probes, s.iterations - 3) << "seed " << seed;
    EXPECT_GE(2 * probes, s.iterations) << "seed " << seed;
  }
}

// ---- robust losses -------------------------------------------------------------------------

TEST(LevenbergMarquardt, RobustLossesDownWeightOutliers) {
  const Scenario scenario = paper_scenario(5, 7);
  Measurements data = scenario.calibration;
  for (int row : {3, 17, 41}) data.readings(row, 0) += 5.0;  // three gross gauge errors
  auto rms_error = [&](const std::string& loss) {
    CalibrationProblem problem(scenario.model, data, scenario.nominal, scenario.free_indices);
    VectorXd x = problem.initial_free_parameters();
    SolverOptions options;
    options.max_iterations = 300;
    if (!loss.empty()) options.loss = RobustLoss::parse(loss);
    const Summary summary = lm()->solve(problem, x, options);
    // The plain fit ends stalled, honestly: with three gross errors its trust region
    // collapses next to configurations where forward kinematics fails, at a point that is
    // not stationary (it used to call that convergence).
    if (!loss.empty()) {
      EXPECT_TRUE(summary.converged()) << loss << ": " << summary.brief_report();
    }
    const VectorXd estimate = problem.full_parameters(x);
    double sum = 0;
    for (int i : scenario.free_indices) sum += std::pow(estimate[i] - scenario.truth[i], 2);
    return std::sqrt(sum / scenario.free_indices.size());
  };
  const double plain = rms_error("");
  const double huber = rms_error("huber:0.05");
  const double cauchy = rms_error("cauchy:0.05");
  EXPECT_LT(huber, 0.5 * plain) << "plain " << plain << " huber " << huber;
  EXPECT_LT(cauchy, 0.5 * plain) << "plain " << plain << " cauchy " << cauchy;
}

TEST(LevenbergMarquardt, LossNoneMatchesNoLoss) {
  const Scenario scenario = paper_scenario(3, 2);
  SolverOptions options;
  const CalibrationRun plain = run_calibration(scenario, *lm(), options, false);
  options.loss = RobustLoss::parse("none");
  const CalibrationRun none = run_calibration(scenario, *lm(), options, false);
  EXPECT_EQ(plain.estimate, none.estimate);
}

// ---- bounds ----------------------------------------------------------------------------------

TEST(LevenbergMarquardt, StaysInsideTheBox) {
  const Scenario scenario = paper_scenario(1, 5);
  const auto problem = scenario.make_problem();
  VectorXd x = problem->initial_free_parameters();
  const VectorXd lower = x.array() - 2.0, upper = x.array() + 2.0;  // truth is up to 5 off
  SolverOptions options;
  options.lower_bounds = lower;
  options.upper_bounds = upper;
  bool inside_every_iterate = true;
  options.callback = [&](const IterationRecord&, const VectorXd& xi) {
    inside_every_iterate = inside_every_iterate && (xi.array() >= lower.array()).all() &&
                           (xi.array() <= upper.array()).all();
    return CallbackAction::kContinue;
  };
  const Summary summary = lm()->solve(*problem, x, options);
  EXPECT_TRUE(inside_every_iterate);
  EXPECT_TRUE((x.array() >= lower.array()).all() && (x.array() <= upper.array()).all());
  EXPECT_NE(summary.termination, TerminationType::kFailed) << summary.brief_report();
  EXPECT_LT(summary.final_cost, summary.initial_cost);
  int at_bound = 0;
  for (int i = 0; i < x.size(); ++i) at_bound += x[i] == lower[i] || x[i] == upper[i];
  EXPECT_GT(at_bound, 0);  // the box really constrained the solution
}

TEST(LevenbergMarquardt, ABoxAroundTheTruthDoesNotChangeTheAnswer) {
  const Scenario scenario = paper_scenario(1, 6);
  const auto problem = scenario.make_problem();
  VectorXd x = problem->initial_free_parameters();
  SolverOptions options;
  options.lower_bounds = VectorXd(x.array() - 6.0);
  options.upper_bounds = VectorXd(x.array() + 6.0);
  const Summary summary = lm()->solve(*problem, x, options);
  EXPECT_TRUE(summary.converged()) << summary.brief_report();
  EXPECT_LT((problem->full_parameters(x) - scenario.truth).lpNorm<Eigen::Infinity>(), 1e-6);
}

// ---- failing evaluations ---------------------------------------------------------------------

TEST(LevenbergMarquardt, AFailedTrialEvaluationIsARejectedStep) {
  FragileRoot problem;
  VectorXd x(1);
  x << 0.5;  // the first Gauss-Newton step lands at 2.25, where evaluation fails
  const Summary summary = lm()->solve(problem, x, SolverOptions{});
  EXPECT_TRUE(summary.converged()) << summary.brief_report();
  EXPECT_NEAR(x[0], std::sqrt(2.0), 1e-9);
  EXPECT_GT(summary.iterations, static_cast<int>(summary.trace.size()) - 1);  // some rejected
  // The failure is told even when the solve converged.
  EXPECT_NE(summary.message.find("residuals failed at"), std::string::npos) << summary.message;
  EXPECT_NE(summary.message.find("outside the valid region"), std::string::npos);
}

TEST(LevenbergMarquardt, StoppingAtTheEdgeOfTheComputableRegionIsNotConvergence) {
  // The unconstrained minimum lies beyond the fence, where residuals cannot be computed:
  // lm creeps along it until its cost test fires, with a gradient that has not vanished.
  kincal::testing::FencedFit problem;
  VectorXd x = kincal::testing::FencedFit::start();
  const Summary summary = lm()->solve(problem, x, SolverOptions{});
  EXPECT_EQ(summary.termination, TerminationType::kDiverged) << summary.brief_report();
  EXPECT_NE(summary.message.find("edge of the region"), std::string::npos) << summary.message;
  EXPECT_NE(summary.message.find(kincal::testing::FencedFit::kReason), std::string::npos);
  EXPECT_LE(x[0], kincal::testing::FencedFit::kFence);
}

TEST(LevenbergMarquardt, DivergesAfterManyUnusableTrials) {
  FragileRoot problem(/*only_start=*/true);
  VectorXd x(1);
  x << 0.5;
  SolverOptions options;
  LevenbergMarquardtSettings settings;
  settings.max_invalid_steps = 4;
  options.backend = std::make_shared<LevenbergMarquardtSettings>(settings);
  const Summary summary = lm()->solve(problem, x, options);
  EXPECT_EQ(summary.termination, TerminationType::kDiverged) << summary.brief_report();
  EXPECT_NE(summary.message.find("outside the valid region"), std::string::npos);
  EXPECT_EQ(x[0], 0.5);  // the best (only) point
}

// ---- generic behaviour -----------------------------------------------------------------------

TEST(LevenbergMarquardt, FitsAGenericProblemWithEitherLinearSolver) {
  for (const char* linear_solver : {"cholesky", "qr"}) {
    for (const char* acceleration : {"true", "false"}) {
      ExponentialFit problem;
      VectorXd x(3);
      x << 1, 2, 0;
      SolverOptions options;
      options.backend = lm()->parse_settings(
          {{"linear_solver", linear_solver}, {"geodesic_acceleration", acceleration}});
      const Summary summary = lm()->solve(problem, x, options);
      EXPECT_TRUE(summary.converged()) << summary.brief_report();
      EXPECT_NEAR(x[0], 3.0, 1e-2);
      EXPECT_NEAR(x[1], 0.7, 1e-2);
      EXPECT_NEAR(x[2], 0.5, 1e-2);
    }
  }
}

TEST(LevenbergMarquardt, ReportsTraceAndEvaluationsConsistently) {
  const Scenario scenario = paper_scenario(5, 1);
  int calls = 0;
  SolverOptions options;
  options.callback = [&](const IterationRecord&, const VectorXd&) {
    ++calls;
    return CallbackAction::kContinue;
  };
  const CalibrationRun run = run_calibration(scenario, *lm(), options, false);
  const Summary& s = run.summary;
  EXPECT_EQ(static_cast<int>(s.trace.size()), calls);
  EXPECT_EQ(s.trace[0].iteration, 0);
  for (std::size_t i = 1; i < s.trace.size(); ++i) {
    EXPECT_GT(s.trace[i].iteration, s.trace[i - 1].iteration);
    EXPECT_LT(s.trace[i].cost, s.trace[i - 1].cost);  // only decreasing steps are accepted
  }
  EXPECT_EQ(s.final_cost, s.trace.back().cost);
  EXPECT_GE(s.residual_evaluations, s.jacobian_evaluations);
  // Every accepted iterate has its Jacobian, except possibly the last: a final step whose
  // predicted decrease is below the tolerance is checked with residuals only.
  EXPECT_GE(s.jacobian_evaluations + 1, static_cast<int>(s.trace.size()));
}

// ---- options ---------------------------------------------------------------------------------

TEST(LevenbergMarquardt, RejectsBadOptions) {
  const auto solver = lm();
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"loss", "huber:1"},  // the loss is SolverOptions::loss, not lm's own
      {"linear_solver", "lu"},       {"initial_trust_radius", "abc"},
      {"initial_trust_radius", "0"}, {"max_invalid_steps", "0"},
      {"max_radius_growth", "1"},    {"geodesic_acceleration", "yes"},
      {"geodesic_step", "2"},        {"min_relative_decrease", "1"},
      {"uphill_steps", "yes"},       {"max_uphill_ratio", "0.5"},
      {"max_uphill_ratio", "inf"},   {"no_such_option", "1"},
  };
  for (const auto& [key, value] : bad)
    EXPECT_THROW(solver->parse_settings({{key, value}}), InvalidSolverOptions)
        << key << "=" << value;
  for (const char* loss : {"tukey:1", "huber:-1", "cauchy:"})
    EXPECT_THROW(RobustLoss::parse(loss), std::invalid_argument) << loss;
  // Settings filled in code are held to the same rules, before any work.
  LevenbergMarquardtSettings growth;
  growth.max_radius_growth = 1;
  LevenbergMarquardtSettings nan_step;
  nan_step.geodesic_step = std::nan("");
  for (const LevenbergMarquardtSettings& settings : {growth, nan_step}) {
    SolverOptions options;
    options.backend = std::make_shared<LevenbergMarquardtSettings>(settings);
    EXPECT_THROW(solver->check_options(options), InvalidSolverOptions);
    ExponentialFit problem;
    VectorXd x = VectorXd::Ones(3);
    EXPECT_THROW(solver->solve(problem, x, options), InvalidSolverOptions);
  }
  SolverOptions good = kincal::testing::with_settings(*solver, {{"linear_solver", "qr"},
                                                                {"initial_trust_radius", "1e3"},
                                                                {"max_invalid_steps", "3"},
                                                                {"uphill_steps", "false"},
                                                                {"max_uphill_ratio", "1"}});
  good.loss = RobustLoss::parse("cauchy:0.1");
  EXPECT_NO_THROW(solver->check_options(good));
  // Every setting in force, defaults included, as text that reads back.
  const auto in_force = solver->settings_in_force(good)->in_force();
  ASSERT_EQ(in_force.size(), LevenbergMarquardtSettings::fields().size());
  EXPECT_EQ(in_force[0], (std::pair<std::string, std::string>{"linear_solver", "qr"}));
  EXPECT_EQ(in_force[1], (std::pair<std::string, std::string>{"initial_trust_radius", "1000"}));
  EXPECT_EQ(in_force[7], (std::pair<std::string, std::string>{"runaway_factor", "none"}));
  EXPECT_EQ(in_force[9], (std::pair<std::string, std::string>{"geodesic_step", "0.1"}));

  SolverOptions wrong_size;
  wrong_size.lower_bounds = VectorXd::Zero(2);
  wrong_size.upper_bounds = VectorXd::Ones(2);
  ExponentialFit problem;
  VectorXd x = VectorXd::Ones(3);
  EXPECT_THROW(solver->solve(problem, x, wrong_size), InvalidSolverOptions);
}

}  // namespace
}  // namespace kincal
