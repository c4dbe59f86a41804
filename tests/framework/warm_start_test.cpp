// Warm starts (framework/least_squares/least_squares_problem.hpp): a calibration problem
// evaluated with one starts forward kinematics from each configuration's last pose, and must
// give what an evaluation from the home pose gives, to the rounding of forward kinematics,
// whatever was evaluated before (a nearby point, a far one, one where it failed).

#include <gtest/gtest.h>

#include <limits>

#include "kincal/framework/calibration/prior_problem.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "solvers/solver_fixtures.hpp"

namespace kincal {
namespace {

using kincal::testing::paper_scenario;

// max |a - b| relative to max |b|.
double relative_difference(const MatrixXd& a, const MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

void expect_same_as_cold(const LeastSquaresProblem& problem, const VectorXd& x, WarmStart& warm) {
  VectorXd r_cold, r_warm;
  MatrixXd J_cold, J_warm;
  ASSERT_TRUE(problem.evaluate(x, &r_cold, &J_cold));
  ASSERT_TRUE(problem.evaluate(x, &r_warm, &J_warm, nullptr, 1, &warm));
  // Residuals are differences of ~500 mm leg lengths: rounding of 1e-13 mm against residuals
  // of a few mm here.
  EXPECT_LT((r_warm - r_cold).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_LT(relative_difference(J_warm, J_cold), 1e-10);
}

TEST(WarmStart, AClosedChainProblemMakesOneAndASerialArmNone) {
  const Scenario hexapod = paper_scenario(5, 1);
  EXPECT_NE(hexapod.make_problem()->make_warm_start(), nullptr);
  const auto puma = ModelRegistry::global().make_preset("puma560");
  const Measurements data{MatrixXd::Zero(3, puma->mechanism().num_actuators()),
                          MatrixXd::Zero(3, puma->num_readings())};
  const CalibrationProblem arm(puma, data, puma->parameters().nominal_values(),
                               puma->parameters().free_indices());
  EXPECT_EQ(arm.make_warm_start(), nullptr);  // closed-form forward kinematics: nothing to carry
}

TEST(WarmStart, GivesTheColdEvaluationAfterANearbyOneAFarOneAndAFailedOne) {
  const Scenario s = paper_scenario(5, 1);
  const auto problem = s.make_problem();
  const VectorXd x0 = problem->initial_free_parameters();
  const std::unique_ptr<WarmStart> warm = problem->make_warm_start();
  ASSERT_NE(warm, nullptr);
  VectorXd r;
  expect_same_as_cold(*problem, x0, *warm);  // the first evaluation: from home

  VectorXd nearby = x0;
  nearby.array() += 0.01;  // mm: as lm's late steps
  ASSERT_TRUE(problem->evaluate(nearby, &r, nullptr, nullptr, 1, warm.get()));
  expect_same_as_cold(*problem, x0, *warm);

  VectorXd far = x0;
  far.array() += 30;  // mm: a line search's wild probe; the poses move far from home
  ASSERT_TRUE(problem->evaluate(far, &r, nullptr, nullptr, 1, warm.get()));
  expect_same_as_cold(*problem, x0, *warm);

  const VectorXd broken = VectorXd::Constant(x0.size(), std::numeric_limits<double>::quiet_NaN());
  std::string why;
  EXPECT_FALSE(problem->evaluate(broken, &r, nullptr, &why, 1, warm.get()));
  EXPECT_NE(why.find("forward kinematics"), std::string::npos) << why;
  expect_same_as_cold(*problem, x0, *warm);
}

// The implicit formulation's verdict starts forward kinematics from its closed poses.
TEST(WarmStart, FromGivenPosesGivesTheColdEvaluation) {
  const Scenario s = paper_scenario(5, 1);
  const auto problem = s.make_problem();
  const VectorXd x0 = problem->initial_free_parameters();
  const MeasurementModel& model = problem->model();
  const VectorXd full = problem->full_parameters(x0);
  std::vector<Pose> closed,
      home(static_cast<std::size_t>(problem->num_residual_blocks()), model.mechanism().home_pose());
  for (int j = 0; j < problem->num_residual_blocks(); ++j) {
    const ForwardKinematicsResult fk = model.mechanism().forward_kinematics(
        full, problem->data().actuators.row(j).transpose(), model.mechanism().home_pose(),
        model.forward_kinematics_options());
    ASSERT_TRUE(fk.ok());
    closed.push_back(fk.pose);
  }
  for (const auto& poses : {closed, home}) {
    const std::unique_ptr<WarmStart> warm = problem->make_warm_start(poses);
    ASSERT_NE(warm, nullptr);
    expect_same_as_cold(*problem, x0, *warm);
  }
  EXPECT_THROW(problem->make_warm_start(std::vector<Pose>(3)), std::invalid_argument);
}

TEST(WarmStart, AWrappedProblemPassesItsDataProblemsOn) {
  const Scenario s = paper_scenario(5, 1);
  const auto problem = s.make_problem();
  Prior prior;
  prior.mean = problem->initial_free_parameters();
  prior.std = VectorXd::Constant(prior.mean.size(), 2.0);
  const PriorProblem with_prior(*problem, prior);
  const std::unique_ptr<WarmStart> warm = with_prior.make_warm_start();
  ASSERT_NE(warm, nullptr);
  VectorXd nearby = prior.mean;
  nearby.array() += 0.01;
  VectorXd r;
  ASSERT_TRUE(with_prior.evaluate(nearby, &r, nullptr, nullptr, 1, warm.get()));
  expect_same_as_cold(with_prior, prior.mean, *warm);
}

TEST(WarmStart, LmEndsWhereItDidFromColdStartsToWithinTheFlatValley) {
  // lm uses a warm start; the same solve from cold starts (a problem that offers none) must end
  // at the same minimum. On case 5 (condition number ~1e5) the end point may move along the
  // valley's floor by far less than the estimates' std (about 1 mm here).
  class Cold : public LeastSquaresProblem {
   public:
    explicit Cold(const LeastSquaresProblem& p) : p_(p) {}
    int num_parameters() const override { return p_.num_parameters(); }
    int num_residual_blocks() const override { return p_.num_residual_blocks(); }
    int residuals_per_block() const override { return p_.residuals_per_block(); }
    bool evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                        Eigen::Ref<MatrixXd>* jacobian, std::string* why) const override {
      return p_.evaluate_block(block, x, residuals, jacobian, why);
    }

   private:
    const LeastSquaresProblem& p_;
  };
  const auto lm = SolverRegistry::global().create("lm");
  for (int seed = 1; seed <= 5; ++seed) {
    const Scenario s = paper_scenario(5, static_cast<std::uint64_t>(seed));
    const auto problem = s.make_problem();
    const Cold cold(*problem);
    VectorXd x_warm = problem->initial_free_parameters(), x_cold = x_warm;
    const Summary warm = lm->solve(*problem, x_warm, SolverOptions{});
    const Summary from_home = lm->solve(cold, x_cold, SolverOptions{});
    ASSERT_TRUE(warm.converged()) << warm.message;
    ASSERT_TRUE(from_home.converged()) << from_home.message;
    EXPECT_NEAR(warm.final_cost, from_home.final_cost, 1e-9 * from_home.final_cost) << seed;
    EXPECT_LT((x_warm - x_cold).cwiseAbs().maxCoeff(), 1e-3) << seed;
  }
}

}  // namespace
}  // namespace kincal
