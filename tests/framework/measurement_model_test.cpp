// The chain rule through forward kinematics: measurement-model and calibration-problem
// Jacobians against central finite differences, and bit-for-bit reproducibility.

#include "kincal/framework/kinematics/measurement_model.hpp"

#include <gtest/gtest.h>

#include "jacobian_check.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/calibration/calibration_problem.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/models/presets.hpp"

namespace kincal {
namespace {

using kincal::testing::jacobians_match;
using kincal::testing::numerical_jacobian;

TEST(MeasurementModel, CombinesMechanismAndSensorParameters) {
  const auto model = make_cube_hexapod();
  EXPECT_EQ(model->num_parameters(), 6 * 7 + 7);
  EXPECT_EQ(model->num_readings(), 1);
  EXPECT_EQ(model->parameters().num_free(), 24);
  EXPECT_EQ(model->parameters()[model->parameters().index_of("gauge.offset")].free, false);
  EXPECT_EQ(model->parameters()[model->parameters().index_of("leg4.platform.y")].free, true);
  EXPECT_EQ(model->parameters()[model->parameters().index_of("leg1.base.x")].free, false);
  EXPECT_EQ(model->parameters()[model->parameters().index_of("leg2.offset")].free, false);
}

TEST(MeasurementModel, ReadingJacobianMatchesFiniteDifferencesForEveryParameter) {
  const auto model = make_cube_hexapod();
  const VectorXd params = model->parameters().nominal_values();
  auto ws = model->make_workspace();
  Random rng(21);
  for (int trial = 0; trial < 5; ++trial) {
    VectorXd q(6);
    for (int i = 0; i < 6; ++i) q[i] = 354.0 + rng.symmetric(20.0);
    VectorXd reading(1);
    MatrixXd J(1, params.size());
    Eigen::Ref<MatrixXd> J_ref(J);
    ASSERT_TRUE(model->predict(params, q, reading, &J_ref, ws).ok());
    auto reading_at = [&](const VectorXd& p) {
      VectorXd r(1);
      EXPECT_TRUE(model->predict(p, q, r, nullptr, ws).ok());
      return r;
    };
    EXPECT_TRUE(jacobians_match(J, numerical_jacobian(reading_at, params, 1e-5), 1e-6,
                                model->parameters().names()))
        << "trial " << trial;
  }
}

TEST(CalibrationProblem, JacobianOfFreeParametersMatchesFiniteDifferences) {
  ScenarioOptions options;
  options.num_configurations = 12;
  options.noise_half_width.set(kincal::kMillimetre, 0.01);
  options.num_validation = 1;
  const Scenario scenario = make_scenario(make_cube_hexapod(), options);
  const auto problem = scenario.make_problem();
  const VectorXd x = problem->initial_free_parameters();
  VectorXd r;
  MatrixXd J;
  ASSERT_TRUE(problem->evaluate(x, &r, &J));
  EXPECT_EQ(J.rows(), 12);
  EXPECT_EQ(J.cols(), 24);
  auto residuals_at = [&](const VectorXd& p) {
    VectorXd out;
    EXPECT_TRUE(problem->evaluate(p, &out, nullptr));
    return out;
  };
  EXPECT_TRUE(jacobians_match(J, numerical_jacobian(residuals_at, x, 1e-5), 1e-6,
                              problem->parameter_names()));
}

TEST(CalibrationProblem, ThreadedEvaluationEqualsSerialBitForBit) {
  ScenarioOptions options;
  options.num_configurations = 2000;
  options.num_validation = 1;
  const Scenario scenario = make_scenario(make_cube_hexapod(), options);
  const auto problem = scenario.make_problem();
  const VectorXd x = problem->initial_free_parameters();
  VectorXd r1, r2;
  MatrixXd J1, J2;
  ASSERT_TRUE(problem->evaluate(x, &r1, &J1, nullptr, 1));
  ASSERT_TRUE(problem->evaluate(x, &r2, &J2, nullptr, 4));
  EXPECT_TRUE(r1 == r2);
  EXPECT_TRUE(J1 == J2);
}

TEST(CalibrationProblem, FailingForwardKinematicsIsReportedWithTheConfiguration) {
  const auto model = make_cube_hexapod();
  Measurements data;
  data.actuators = MatrixXd::Constant(3, 6, 354.0);
  data.actuators(1, 2) = -5.0;  // negative leg length in configuration 2
  data.readings = MatrixXd::Constant(3, 1, 500.0);
  CalibrationProblem problem(model, data, model->parameters().nominal_values(),
                             model->parameters().free_indices());
  VectorXd r;
  std::string why;
  EXPECT_FALSE(problem.evaluate(problem.initial_free_parameters(), &r, nullptr, &why));
  EXPECT_NE(why.find("configuration 2"), std::string::npos) << why;
}

TEST(Simulation, SameSeedReproducesBitForBit) {
  ScenarioOptions options;
  options.num_configurations = 40;
  options.noise_half_width.set(kincal::kMillimetre, 0.00125);
  options.num_validation = 30;
  options.seed = 1234;
  const Scenario a = make_scenario(make_cube_hexapod(), options);
  const Scenario b = make_scenario(make_cube_hexapod(), options);
  EXPECT_TRUE(a.truth == b.truth);
  EXPECT_TRUE(a.calibration.actuators == b.calibration.actuators);
  EXPECT_TRUE(a.calibration.readings == b.calibration.readings);
  EXPECT_TRUE(a.validation_actuators == b.validation_actuators);

  options.seed = 1235;
  const Scenario c = make_scenario(make_cube_hexapod(), options);
  EXPECT_FALSE(a.truth == c.truth);
}

TEST(Simulation, NoiseLevelDoesNotChangeTruthOrConfigurations) {
  ScenarioOptions options;
  options.num_validation = 1;
  const Scenario quiet = make_scenario(make_cube_hexapod(), options);
  options.noise_half_width.set(kincal::kMillimetre, 0.0125);
  const Scenario noisy = make_scenario(make_cube_hexapod(), options);
  EXPECT_TRUE(quiet.truth == noisy.truth);
  EXPECT_TRUE(quiet.calibration.actuators == noisy.calibration.actuators);
  const double max_noise =
      (quiet.calibration.readings - noisy.calibration.readings).cwiseAbs().maxCoeff();
  EXPECT_GT(max_noise, 0.0);
  EXPECT_LE(max_noise, 0.0125);
}

TEST(Simulation, TruthDiffersFromNominalOnlyOnFreeParametersWithinTheBound) {
  ScenarioOptions options;
  options.param_error_half_width.set(kincal::kMillimetre, 5.0);
  options.num_validation = 1;
  const Scenario s = make_scenario(make_cube_hexapod(), options);
  const auto& params = s.model->parameters();
  for (int i = 0; i < params.size(); ++i) {
    const double d = std::abs(s.truth[i] - s.nominal[i]);
    if (params[i].free)
      EXPECT_LE(d, 5.0) << params[i].name;
    else
      EXPECT_EQ(d, 0.0) << params[i].name;
  }
}

TEST(Simulation, ValidationErrorsVanishForTheTrueModel) {
  ScenarioOptions options;
  options.num_validation = 20;
  const Scenario s = make_scenario(make_cube_hexapod(), options);
  const PoseErrorStats exact = validation_errors(s, s.truth);
  EXPECT_LT(exact.position_max_mm, 1e-9);
  EXPECT_LT(exact.orientation_max_rad, 1e-12);
  const PoseErrorStats nominal = validation_errors(s, s.nominal);
  EXPECT_GT(nominal.position_mean_mm, 0.1);
  EXPECT_GE(nominal.position_max_mm, nominal.position_mean_mm);
}

}  // namespace
}  // namespace kincal
