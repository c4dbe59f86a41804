// MAP estimation through PriorProblem with every featured backend: on a linear problem the
// estimate is the closed form (A^T A + L)^-1 (A^T y + L mu); on the paper's case 4 every
// least-squares backend reaches the same MAP estimate. A backend left out of the build is
// skipped with the registry's reason.

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>

#include "kincal/framework/base/random.hpp"
#include "kincal/framework/calibration/prior_problem.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/presets.hpp"
#include "solver_fixtures.hpp"

namespace kincal {
namespace {

using kincal::testing::backend_test_name;
using kincal::testing::every_backend;
using kincal::testing::why_not_built;

bool is_least_squares(const std::string& name) {
  for (const auto& info : SolverRegistry::global().list())
    if (info.name == name) return info.kind == SolverKind::kLeastSquares;
  return false;
}

// y = A x + noise, 30 readings, 4 parameters; A's last column nearly repeats its third, so
// that the prior visibly moves the estimate.
class LinearFit : public LeastSquaresProblem {
 public:
  LinearFit() : A_(30, 4), y_(30) {
    Random rng(derive_seed(5, 1));
    for (int i = 0; i < 30; ++i) {
      const double t = i / 29.0;
      A_.row(i) << 1, t, t * t, t * t + 1e-3 * rng.symmetric(1.0);
      y_[i] = 1 + 2 * t - t * t + 0.05 * rng.symmetric(1.0);
    }
  }
  int num_parameters() const override { return 4; }
  int num_residual_blocks() const override { return 30; }
  int residuals_per_block() const override { return 1; }
  bool evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                      std::string*) const override {
    r[0] = A_.row(block).dot(x) - y_[block];
    if (J) *J = A_.row(block);
    return true;
  }
  const MatrixXd& A() const { return A_; }
  const VectorXd& y() const { return y_; }

 private:
  MatrixXd A_;
  VectorXd y_;
};

class PriorConformance : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    const std::string why = why_not_built(GetParam());
    if (!why.empty()) GTEST_SKIP() << why;
  }
  std::unique_ptr<Solver> solver() const { return SolverRegistry::global().create(GetParam()); }
};

TEST_P(PriorConformance, LinearProblemReachesTheClosedFormMap) {
  const LinearFit data;
  Prior prior;
  prior.mean = (VectorXd(4) << 0.8, 2.5, -0.5, 0).finished();
  prior.std = (VectorXd(4) << 0.3, 0, 0.5, 0.2).finished();
  const PriorProblem problem(data, prior);
  const MatrixXd Lambda = prior.precision().asDiagonal();
  const VectorXd expected = (data.A().transpose() * data.A() + Lambda)
                                .ldlt()
                                .solve(data.A().transpose() * data.y() + Lambda * prior.mean);
  // Least squares alone is far from it: the prior matters here.
  const VectorXd ml = data.A().colPivHouseholderQr().solve(data.y());
  ASSERT_GT((ml - expected).norm(), 0.1);

  SolverOptions options;
  const bool exact = is_least_squares(GetParam());
  options.max_iterations = exact ? 100 : 20000;
  if (GetParam().rfind("nlopt:LN_", 0) == 0)
    options.backend = solver()->parse_settings({{"initial_step", "0.1"}});
  VectorXd x = VectorXd::Zero(4);
  const Summary summary = solver()->solve(problem, x, options);
  if (exact) {
    EXPECT_EQ(summary.termination, TerminationType::kConverged) << summary.brief_report();
  }
  EXPECT_LT((x - expected).cwiseAbs().maxCoeff(), exact ? 1e-8 : 1e-4)
      << summary.brief_report() << "\nx " << x.transpose() << "\nexpected " << expected.transpose();
}

// The paper's case 4 (40 configurations, gauge noise U[-0.0125, 0.0125] mm) with the prior
// the parameter errors were drawn from (U[-5, 5] mm: std 5 / sqrt(3) mm).
const Scenario& case4_with_prior() {
  static const Scenario scenario = [] {
    ScenarioOptions options;
    options.num_configurations = paper_case(4).num_configurations;
    options.noise_half_width.set(kincal::kMillimetre, paper_case(4).noise_half_width);
    options.prior_std.set(kincal::kMillimetre, 5 / std::sqrt(3.0));
    options.num_validation = 50;
    options.seed = 4;
    return make_scenario(make_cube_hexapod(), options);
  }();
  return scenario;
}

// The MAP estimate, by gn with tight tolerances (the reference the others must match).
const VectorXd& reference_map() {
  static const VectorXd x = [] {
    SolverOptions options;
    options.function_tolerance = options.parameter_tolerance = 1e-14;
    return run_calibration(case4_with_prior(), *SolverRegistry::global().create("gn"), options,
                           false)
        .estimate;
  }();
  return x;
}

// Least-squares backends within 1e-5 mm of the reference, converged. The prior conditions the
// problem well enough that the gradient-based NLopt minimisers get there too (within 1e-3 mm,
// up to 20000 evaluations; measured 1e-5 to 1e-4 mm); the derivative-free ones and MMA are
// held to the small problems only, as in conformance_test.cpp.
TEST_P(PriorConformance, EveryBackendReachesTheSameMapOnTheHexapod) {
  const std::string& name = GetParam();
  const bool exact = is_least_squares(name);
  if (!exact && (name.rfind("nlopt:LN_", 0) == 0 || name == "nlopt:LD_MMA"))
    GTEST_SKIP() << name << ": derivative-free and MMA are held to the linear problem only";
  const Scenario& scenario = case4_with_prior();
  SolverOptions options;
  if (!exact) options.max_iterations = 20000;
  const CalibrationRun run = run_calibration(scenario, *solver(), options, false);
  if (exact) {
    EXPECT_EQ(run.summary.termination, TerminationType::kConverged) << run.summary.brief_report();
  }
  double worst = 0;
  for (int i : scenario.free_indices)
    worst = std::max(worst, std::abs(run.estimate[i] - reference_map()[i]));
  EXPECT_LT(worst, exact ? 1e-5 : 1e-3) << run.summary.brief_report();  // mm
  // The prior helps on this case: the MAP estimate is closer to the truth than nominal is.
  EXPECT_LT(run.after.position_mean_mm, run.before.position_mean_mm);
}

INSTANTIATE_TEST_SUITE_P(Backends, PriorConformance, ::testing::ValuesIn(every_backend()),
                         backend_test_name);

}  // namespace
}  // namespace kincal
