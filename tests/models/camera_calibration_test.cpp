// Calibrating a robot, a camera's intrinsics and distortion and both mounts from simulated
// pixels, eye-to-hand and eye-in-hand (the presets ur5-urdf-camera and ur5-urdf-eye-in-hand):
// over repeated noise draws the estimates scatter as the reported uncertainty says (the
// Cramér-Rao bound of the linearised problem: efficiency 1) and centre on the truth; simulated
// views keep only configurations that see the whole target.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "kincal/framework/analysis/calibration_report.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/camera.hpp"
#include "kincal/models/presets.hpp"

namespace kincal {
namespace {

class CameraCalibration : public ::testing::TestWithParam<const char*> {};

TEST_P(CameraCalibration, EstimatesScatterAsTheReportedUncertaintySaysAndCentreOnTheTruth) {
  ScenarioOptions options;
  options.num_configurations = 25;
  options.num_validation = 0;
  options.seed = 5;
  const Scenario exact = make_scenario(make_preset(GetParam()), options);  // noise-free
  // Every drawn view sees the whole board (Camera::drop_unseen): no reading is missing.
  EXPECT_FALSE(exact.calibration.readings.hasNaN());

  const auto solver = SolverRegistry::global().create("lm");
  // 0.2 px of uniform noise: small enough for the linearisation that sigma^2 (J^T J)^-1
  // describes, the size a chessboard's sub-pixel corners reach.
  const double a = 0.2 * std::sqrt(3.0), sigma = 0.2;
  const int trials = 60;
  const int n = static_cast<int>(exact.free_indices.size());
  MatrixXd estimates(trials, n);
  VectorXd mean_reported = VectorXd::Zero(n);
  double mean_sigma_hat = 0;
  Random rng(77);
  for (int t = 0; t < trials; ++t) {
    Measurements data = exact.calibration;
    for (Eigen::Index j = 0; j < data.readings.size(); ++j)
      data.readings.data()[j] += rng.symmetric(a);
    CalibrationProblem problem(exact.model, data, exact.nominal, exact.free_indices);
    VectorXd x = problem.initial_free_parameters();
    const Summary summary = solver->solve(problem, x, SolverOptions{});
    ASSERT_TRUE(summary.converged()) << summary.message;
    const CalibrationReport report = make_calibration_report(problem, x, summary, {});
    estimates.row(t) = x.transpose();
    mean_reported += report.uncertainty.std / trials;
    mean_sigma_hat += report.uncertainty.sigma / trials;
  }
  EXPECT_NEAR(mean_sigma_hat, sigma, 0.05 * sigma);
  std::vector<double> ratios;
  for (int i = 0; i < n; ++i) {
    const std::string& name = exact.model->parameters()[exact.free_indices[i]].name;
    const VectorXd column = estimates.col(i);
    const double mean = column.mean();
    const double spread = std::sqrt((column.array() - mean).square().sum() / (trials - 1));
    // The sample std of 60 draws has a relative standard error of about 9 %; 3.5 of them.
    EXPECT_NEAR(spread / mean_reported[i], 1.0, 0.32) << name;
    ratios.push_back(spread / mean_reported[i]);
    EXPECT_NEAR(mean, exact.truth[exact.free_indices[i]], 4 * spread / std::sqrt(double(trials)))
        << name;
  }
  std::sort(ratios.begin(), ratios.end());
  std::printf("%s: %d free parameters, scatter / reported std: min %.3f median %.3f max %.3f\n",
              GetParam(), n, ratios.front(), ratios[ratios.size() / 2], ratios.back());
}

INSTANTIATE_TEST_SUITE_P(Mountings, CameraCalibration,
                         ::testing::Values("ur5-urdf-camera", "ur5-urdf-eye-in-hand"),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

}  // namespace
}  // namespace kincal
