// Predicted pose error over the workspace: its pieces (quantiles, the Jacobians it
// propagates through) against known values and finite differences, and the whole against a
// Monte Carlo of parameter errors through the exact forward kinematics.

#include "kincal/framework/analysis/pose_accuracy.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "jacobian_check.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/models/presets.hpp"

namespace kincal {
namespace {

double gaussian(Random& rng) {
  // Box-Muller; 1 - u keeps the logarithm finite.
  const double u = 1.0 - rng.uniform01(), v = rng.uniform01();
  return std::sqrt(-2 * std::log(u)) * std::cos(2 * M_PI * v);
}

TEST(PoseAccuracy, ChiSquareQuantilesMatchTables) {
  EXPECT_NEAR(chi_square_quantile(0.95, 1), 3.841458821, 1e-8);
  EXPECT_NEAR(chi_square_quantile(0.95, 2), 5.991464547, 1e-8);
  EXPECT_NEAR(chi_square_quantile(0.95, 3), 7.814727903, 1e-8);
  EXPECT_NEAR(chi_square_quantile(0.5, 3), 2.365973884, 1e-8);
  EXPECT_TRUE(std::isnan(chi_square_quantile(1.0, 3)));
}

TEST(PoseAccuracy, ErrorNormQuantileIsExactForIsotropicErrors) {
  const Matrix3d cov = 4.0 * Matrix3d::Identity();
  EXPECT_NEAR(error_norm_quantile(cov, 0.95), 2.0 * std::sqrt(7.814727903), 1e-8);
  EXPECT_EQ(error_norm_quantile(Matrix3d::Zero(), 0.95), 0.0);
}

TEST(PoseAccuracy, ErrorNormQuantileMatchesMonteCarloForAnisotropicErrors) {
  Matrix3d A;
  A << 3, 1, 0, 1, 1, 0.2, 0, 0.2, 0.05;  // eigenvalues spread over two decades
  const Matrix3d cov = A * A.transpose();
  const Eigen::LLT<Matrix3d> llt(cov);
  Random rng(11);
  std::vector<double> norms;
  for (int i = 0; i < 200000; ++i) {
    const Vector3d z(gaussian(rng), gaussian(rng), gaussian(rng));
    norms.push_back((llt.matrixL() * z).norm());
  }
  std::sort(norms.begin(), norms.end());
  const double empirical = norms[static_cast<std::size_t>(0.95 * norms.size())];
  EXPECT_NEAR(error_norm_quantile(cov, 0.95), empirical, 0.02 * empirical);
}

// The samples' Jacobians are the free columns of J_pose_params at the given parameters:
// central differences of the pose reached at fixed actuator values.
TEST(PoseAccuracy, WorkspaceJacobiansMatchFiniteDifferences) {
  const auto model = make_cube_hexapod();
  const std::vector<int> free = model->parameters().free_indices();
  VectorXd params = model->parameters().nominal_values();
  for (int i : free) params[i] += 0.7 * std::sin(i);  // away from the nominal values
  const WorkspaceSamples samples = sample_workspace(*model, params, free, 4, 5);
  ASSERT_EQ(samples.J_free.size(), 4u);
  const Mechanism& mechanism = model->mechanism();
  const int n_mech = mechanism.num_parameters();
  for (int s = 0; s < 4; ++s) {
    const VectorXd q = samples.actuators.row(s).transpose();
    const Pose base =
        mechanism.forward_kinematics(params.head(n_mech), q, mechanism.home_pose()).pose;
    const auto pose_of = [&](const VectorXd& x) {
      VectorXd p = params;
      for (std::size_t c = 0; c < free.size(); ++c) p[free[c]] = x[static_cast<int>(c)];
      const Pose pose = mechanism.forward_kinematics(p.head(n_mech), q, base).pose;
      VectorXd delta(6);
      delta << pose.translation - base.translation,
          log_so3(pose.rotation * base.rotation.transpose());
      return delta;
    };
    VectorXd x(free.size());
    for (std::size_t c = 0; c < free.size(); ++c) x[static_cast<int>(c)] = params[free[c]];
    EXPECT_TRUE(testing::jacobians_match(samples.J_free[s],
                                         testing::numerical_jacobian(pose_of, x, 1e-5), 1e-6));
  }
}

// The prediction against the spread of the exact pose errors when the parameters are drawn
// from the covariance (small, so that first order holds).
TEST(PoseAccuracy, PredictionMatchesMonteCarloOfParameterErrors) {
  const auto model = make_cube_hexapod();
  const std::vector<int> free = model->parameters().free_indices();
  const int n = static_cast<int>(free.size());
  const VectorXd nominal = model->parameters().nominal_values();
  MatrixXd B = MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j <= i; ++j) B(i, j) = 0.05 * std::cos(3.0 * i + j) + (i == j ? 0.1 : 0.0);
  const MatrixXd cov = B * B.transpose();
  const WorkspaceSamples samples = sample_workspace(*model, nominal, free, 20, 9);
  const PoseErrorPrediction predicted = predict_pose_errors(samples, cov);
  EXPECT_EQ(predicted.samples, 20);
  EXPECT_LE(predicted.position_mean_1sigma, predicted.position_max_1sigma);
  EXPECT_LT(predicted.position_mean_1sigma, predicted.position_mean_95);

  const Mechanism& mechanism = model->mechanism();
  const int n_mech = mechanism.num_parameters();
  Random rng(21);
  double position_ss = 0, orientation_ss = 0;
  int count = 0, inside_95 = 0;
  const int draws = 400;
  std::vector<Pose> base(20);
  for (int s = 0; s < 20; ++s)
    base[s] = mechanism
                  .forward_kinematics(nominal.head(n_mech), samples.actuators.row(s).transpose(),
                                      mechanism.home_pose())
                  .pose;
  for (int d = 0; d < draws; ++d) {
    VectorXd z(n);
    for (int i = 0; i < n; ++i) z[i] = gaussian(rng);
    const VectorXd dp = B * z;
    VectorXd params = nominal;
    for (int i = 0; i < n; ++i) params[free[i]] += dp[i];
    for (int s = 0; s < 20; ++s) {
      const ForwardKinematicsResult fk = mechanism.forward_kinematics(
          params.head(n_mech), samples.actuators.row(s).transpose(), base[s]);
      ASSERT_TRUE(fk.ok());
      const double e = (fk.pose.translation - base[s].translation).norm();
      position_ss += e * e;
      orientation_ss += log_so3(fk.pose.rotation * base[s].rotation.transpose()).squaredNorm();
      const Matrix6d pose_cov = samples.J_free[s] * cov * samples.J_free[s].transpose();
      inside_95 += e <= error_norm_quantile(pose_cov.topLeftCorner<3, 3>(), 0.95);
      ++count;
    }
  }
  EXPECT_NEAR(std::sqrt(position_ss / count), predicted.position_rms,
              0.05 * predicted.position_rms);
  EXPECT_NEAR(std::sqrt(orientation_ss / count), predicted.orientation_rms,
              0.05 * predicted.orientation_rms);
  EXPECT_NEAR(static_cast<double>(inside_95) / count, 0.95, 0.01);
}

TEST(PoseAccuracy, NominalStdIsThePriorOrTheSimulatedErrorSpread) {
  auto model = make_cube_hexapod();
  const std::vector<int> free = model->parameters().free_indices();
  VectorXd std = nominal_parameter_std(*model, free);
  for (int i = 0; i < std.size(); ++i) EXPECT_DOUBLE_EQ(std[i], 5 / std::sqrt(3.0));
  model->parameters().for_each_matching("leg4.*", [](Parameter& p) { p.prior_std = 0.5; });
  std = nominal_parameter_std(*model, free);
  for (std::size_t c = 0; c < free.size(); ++c) {
    const bool leg4 = model->parameters()[free[c]].name.rfind("leg4.", 0) == 0;
    EXPECT_DOUBLE_EQ(std[static_cast<int>(c)], leg4 ? 0.5 : 5 / std::sqrt(3.0));
  }
}

TEST(PoseAccuracy, NonFiniteCovarianceGivesNaN) {
  const auto model = make_cube_hexapod();
  const std::vector<int> free = model->parameters().free_indices();
  const WorkspaceSamples samples =
      sample_workspace(*model, model->parameters().nominal_values(), free, 3, 1);
  MatrixXd cov = MatrixXd::Identity(free.size(), free.size());
  cov(0, 0) = NAN;
  EXPECT_TRUE(std::isnan(predict_pose_errors(samples, cov).position_rms));
}

}  // namespace
}  // namespace kincal
