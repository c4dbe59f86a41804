// Experiment design with a camera (issue 38): the candidates keep only the views in which the
// target is in view and hold exactly the information of the points seen, and the exchange,
// which handles a view's many readings as one block, chooses designs better than random ones
// and within the relaxation's bound.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "kincal/framework/design/experiment_design.hpp"
#include "kincal/models/presets.hpp"

namespace kincal {
namespace {

// The eye-to-hand UR5 with its joints swept over twice the preset's box, so that many drawn
// configurations turn the board away from the camera or out of the image.
std::shared_ptr<MeasurementModel> wide_camera_model() {
  auto model = std::make_shared<MeasurementModel>(*make_preset("ur5-urdf-camera"));
  const VectorXd ranges = model->actuator_ranges();
  const auto names = model->mechanism().actuator_names();
  for (std::size_t i = 0; i < names.size(); ++i)
    model->set_actuator_range(names[i], 2 * ranges[static_cast<Eigen::Index>(i)]);
  model->set_reading_std("*", 0.3);
  return model;
}

DesignOptions camera_design_options(DesignCriterion criterion) {
  DesignOptions options;
  options.criterion = criterion;
  options.count = 20;
  options.num_random = 600;
  options.seed = 3;
  return options;
}

TEST(CameraDesign, CandidatesAreViewsInWhichTheTargetIsSeenWithExactlyTheirInformation) {
  const auto model = wide_camera_model();
  const DesignOptions options = camera_design_options(DesignCriterion::kD);
  const DesignSetup setup = make_design_setup(*model, options, nullptr);
  const DesignCandidates c = make_design_candidates(*model, setup, options);
  const int n = static_cast<int>(setup.free_indices.size());
  const int k = model->num_readings();
  ASSERT_GT(k, n);  // a view has more readings than free parameters: stored as a factor
  EXPECT_GT(c.rejected_unseen, 50) << "the wide box should turn the board away often";
  ASSERT_GT(c.size(), 100);

  const VectorXd nominal = model->parameters().nominal_values();
  auto ws = model->make_workspace();
  VectorXd predicted(k), seen(k);
  MatrixXd J(k, model->num_parameters());
  Eigen::Ref<MatrixXd> J_ref(J);
  int partial = 0;
  for (int i = 0; i < c.size(); ++i) {
    const VectorXd q = c.configurations.row(c.configuration[i]).transpose();
    const ForwardKinematicsResult fk = model->predict(nominal, q, predicted, &J_ref, ws);
    ASSERT_TRUE(fk.ok());
    model->simulate_at_pose(nominal, fk.pose, seen);
    const int taken = static_cast<int>((!seen.array().isNaN()).count());
    // In view: what simulate would measure there, and something is.
    ASSERT_GT(taken, 0) << "candidate " << i;
    EXPECT_EQ(c.readings[i], taken) << "candidate " << i;
    partial += taken < k;
    // The stored rows carry exactly the information of the readings seen (whitened,
    // normalised): X^T X = R^T R.
    MatrixXd X = MatrixXd::Zero(k, n);
    for (int r = 0; r < k; ++r) {
      if (std::isnan(seen[r])) continue;
      for (int p = 0; p < n; ++p)
        X(r, p) = J(r, setup.free_indices[p]) * setup.scale[p] / setup.noise_std[r];
    }
    const auto R = c.rows.middleRows(c.row_offset[i], c.row_offset[i + 1] - c.row_offset[i]);
    EXPECT_EQ(R.rows(), n);
    const MatrixXd expected = X.transpose() * X;
    EXPECT_LE((R.transpose() * R - expected).norm(), 1e-10 * expected.norm()) << "candidate " << i;
  }
  // The board is found whole or not at all (a grid target): no partial views.
  EXPECT_EQ(partial, 0);
}

class CameraDesignCriterion : public ::testing::TestWithParam<DesignCriterion> {};

TEST_P(CameraDesignCriterion, BeatsRandomDesignsAndRespectsTheBound) {
  const auto model = wide_camera_model();
  const DesignOptions options = camera_design_options(GetParam());
  const DesignRun run = run_design(*model, options);
  const int n = static_cast<int>(run.setup.free_indices.size());
  ASSERT_EQ(static_cast<int>(run.result.chosen.size()), options.count);
  const std::vector<int> distinct = [&] {
    std::vector<int> sorted = run.result.chosen;
    std::sort(sorted.begin(), sorted.end());
    sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
    return sorted;
  }();
  EXPECT_EQ(distinct.size(), run.result.chosen.size());
  const bool maximised = GetParam() == DesignCriterion::kD || GetParam() == DesignCriterion::kE;
  const auto better = [&](double a, double b) { return maximised ? a > b : a < b; };
  const double value = criterion_value(
      GetParam(), design_information(run.candidates, run.result.chosen, run.setup), run.setup);
  EXPECT_NEAR(value, run.result.criterion_value, 1e-9 * std::abs(value));
  EXPECT_FALSE(better(run.result.greedy_value, value));  // the exchange only improves
  // The template leaves the points out of view missing, and as existing data the chosen
  // views count for the readings they take.
  int taken = 0;
  for (int c : run.result.chosen) taken += run.candidates.readings[c];
  EXPECT_EQ((!run.rows.readings.array().isNaN()).count(), taken);
  EXPECT_EQ(make_design_setup(*model, options, &run.rows).existing_readings, taken);
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const std::vector<int> random = random_design(run.candidates, options.count, seed);
    const double r = criterion_value(
        GetParam(), design_information(run.candidates, random, run.setup), run.setup);
    EXPECT_TRUE(better(value, r)) << "random design " << seed << ": " << r << " vs " << value;
  }
  if (GetParam() != DesignCriterion::kE) {
    const DesignBound bound = design_bound(run.candidates, run.setup, options, run.result.chosen);
    ASSERT_TRUE(std::isfinite(bound.bound));
    EXPECT_FALSE(better(value, bound.bound * (1 + (maximised ? 1e-9 : -1e-9))));
    const double ratio = design_std_ratio_to_bound(GetParam(), value, bound, n);
    EXPECT_GE(ratio, 1 - 1e-9);
    std::printf("criterion %s: chosen %.6g, greedy %.6g, bound %.6g, std ratio to bound %.3f\n",
                to_string(GetParam()), value, run.result.greedy_value, bound.bound, ratio);
  }
}

INSTANTIATE_TEST_SUITE_P(Criteria, CameraDesignCriterion,
                         ::testing::Values(DesignCriterion::kD, DesignCriterion::kA,
                                           DesignCriterion::kI, DesignCriterion::kE),
                         [](const auto& info) { return std::string(to_string(info.param)); });

}  // namespace
}  // namespace kincal
