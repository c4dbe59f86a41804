// PriorProblem: the residuals and Jacobian it appends, checked against finite differences,
// and that its blocks keep the data problem's layout.

#include <gtest/gtest.h>

#include <stdexcept>

#include "jacobian_check.hpp"
#include "kincal/framework/calibration/prior_problem.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/models/presets.hpp"

namespace kincal {
namespace {

// A problem with 3 residuals per block, so that prior blocks are padded.
class ThreeResidualFit : public LeastSquaresProblem {
 public:
  int num_parameters() const override { return 5; }
  int num_residual_blocks() const override { return 4; }
  int residuals_per_block() const override { return 3; }
  bool evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                      std::string*) const override {
    for (int j = 0; j < 3; ++j) {
      const double t = block + 0.3 * j;
      r[j] = x[0] * std::sin(x[1] * t) + x[2] * t * t + x[3] * x[4] - t;
      if (J) J->row(j) << std::sin(x[1] * t), x[0] * t * std::cos(x[1] * t), t * t, x[4], x[3];
    }
    return true;
  }
};

Prior three_of_five() {
  Prior prior;
  prior.mean = (VectorXd(5) << 1, 0.5, -2, 0, 3).finished();
  prior.std = (VectorXd(5) << 0.5, 0, 2, 0.1, 0).finished();
  return prior;
}

TEST(PriorProblem, AppendsOneWhitenedResidualPerParameterWithAPrior) {
  const ThreeResidualFit data;
  const PriorProblem problem(data, three_of_five());
  EXPECT_EQ(problem.num_parameters(), 5);
  EXPECT_EQ(problem.residuals_per_block(), 3);
  EXPECT_EQ(problem.num_residual_blocks(), 4 + 1);  // 3 priors fill one block of 3
  ASSERT_EQ(problem.prior_parameters(), (std::vector<int>{0, 2, 3}));
  const VectorXd x = (VectorXd(5) << 1.5, 0.7, -1, 0.2, 2).finished();
  VectorXd r, r_data;
  MatrixXd J;
  ASSERT_TRUE(problem.evaluate(x, &r, &J));
  ASSERT_TRUE(data.evaluate(x, &r_data, nullptr));
  EXPECT_EQ(r.head(12), r_data);
  EXPECT_DOUBLE_EQ(r[12], (1.5 - 1) / 0.5);
  EXPECT_DOUBLE_EQ(r[13], (-1 - -2) / 2.0);
  EXPECT_DOUBLE_EQ(r[14], (0.2 - 0) / 0.1);
  EXPECT_NEAR(problem.cost(x), 0.5 * r.squaredNorm(), 1e-12);
}

TEST(PriorProblem, PadsTheLastPriorBlockWithZeros) {
  const ThreeResidualFit data;
  Prior prior = three_of_five();
  prior.std[4] = 1;  // 4 priors: two blocks of 3, the second with 2 padding residuals
  const PriorProblem problem(data, prior);
  EXPECT_EQ(problem.num_residual_blocks(), 6);
  const VectorXd x = VectorXd::Constant(5, 7.0);
  VectorXd r;
  MatrixXd J;
  ASSERT_TRUE(problem.evaluate(x, &r, &J));
  EXPECT_DOUBLE_EQ(r[15], (7 - 3) / 1.0);
  EXPECT_EQ(r[16], 0);
  EXPECT_EQ(r[17], 0);
  EXPECT_TRUE(J.bottomRows(2).isZero(0));
}

TEST(PriorProblem, JacobianMatchesFiniteDifferences) {
  const ThreeResidualFit data;
  Prior prior = three_of_five();
  prior.std[4] = 0.25;
  const PriorProblem problem(data, prior);
  const VectorXd x = (VectorXd(5) << 1.5, 0.7, -1, 0.2, 2).finished();
  VectorXd r;
  MatrixXd J;
  ASSERT_TRUE(problem.evaluate(x, &r, &J));
  const MatrixXd numeric = testing::numerical_jacobian(
      [&](const VectorXd& p) {
        VectorXd out;
        EXPECT_TRUE(problem.evaluate(p, &out, nullptr));
        return out;
      },
      x, 1e-6);
  EXPECT_TRUE(testing::jacobians_match(J, numeric, 1e-7));
}

TEST(PriorProblem, JacobianMatchesFiniteDifferencesOnTheHexapod) {
  auto model = make_cube_hexapod();
  model->parameters().set_free("leg1.*", true);  // a mix of seen and weakly seen parameters
  ScenarioOptions options;
  options.num_configurations = 12;
  options.noise_half_width.set(kincal::kMillimetre, 0.01);
  options.num_validation = 0;
  options.seed = 3;
  const Scenario scenario = make_scenario(model, options);
  const auto data = scenario.make_problem();
  Prior prior;
  prior.mean = data->initial_free_parameters();
  prior.std = VectorXd::Constant(data->num_parameters(), 2.0);
  prior.std.head(5).setZero();
  const PriorProblem problem(*data, prior);
  const VectorXd x = prior.mean + VectorXd::Constant(prior.mean.size(), 0.3);
  VectorXd r;
  MatrixXd J;
  ASSERT_TRUE(problem.evaluate(x, &r, &J));
  const MatrixXd numeric = testing::numerical_jacobian(
      [&](const VectorXd& p) {
        VectorXd out;
        EXPECT_TRUE(problem.evaluate(p, &out, nullptr));
        return out;
      },
      x, 1e-5);
  EXPECT_TRUE(testing::jacobians_match(J, numeric, 1e-6, problem.parameter_names()));
  EXPECT_EQ(problem.num_residuals(), 12 + problem.prior_parameters().size());
}

TEST(PriorProblem, ModelPriorTakesTheFreeParametersPriorStd) {
  auto model = make_cube_hexapod();
  model->parameters().for_each_matching("leg4.base.*", [](Parameter& p) { p.prior_std = 2; });
  ScenarioOptions options;
  options.num_configurations = 30;
  options.noise_half_width.set(kincal::kMillimetre, 0.01);  // a prior needs the readings' noise
  options.num_validation = 0;
  const Scenario scenario = make_scenario(model, options);
  const auto data = scenario.make_problem();
  const Prior prior = model_prior(*data);
  const auto names = data->parameter_names();
  ASSERT_EQ(prior.std.size(), static_cast<int>(names.size()));
  for (std::size_t i = 0; i < names.size(); ++i)
    EXPECT_EQ(prior.std[i], names[i].rfind("leg4.base.", 0) == 0 ? 2.0 : 0.0) << names[i];
  EXPECT_EQ(prior.mean, data->initial_free_parameters());
}

TEST(PriorProblem, RejectsBadPriors) {
  const ThreeResidualFit data;
  Prior prior = three_of_five();
  prior.std[1] = -1;
  EXPECT_THROW(PriorProblem(data, prior), std::invalid_argument);
  prior = three_of_five();
  prior.std.resize(4);
  EXPECT_THROW(PriorProblem(data, prior), std::invalid_argument);
  prior = three_of_five();
  prior.mean[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(PriorProblem(data, prior), std::invalid_argument);
}

TEST(PriorProblem, SimulationWithAPriorNeedsNoise) {
  ScenarioOptions options;
  options.prior_std.set(kincal::kMillimetre, 2.9);
  options.num_validation = 0;
  EXPECT_THROW(make_scenario(make_cube_hexapod(), options), std::invalid_argument);
  options.noise_half_width.set(kincal::kMillimetre, 0.0125);
  const Scenario scenario = make_scenario(make_cube_hexapod(), options);
  EXPECT_NEAR(scenario.model->reading_std()[0], 0.0125 / std::sqrt(3.0), 1e-15);
  for (int i : scenario.free_indices) EXPECT_EQ(scenario.model->parameters()[i].prior_std, 2.9);
}

}  // namespace
}  // namespace kincal
