// ISO 9283 statistics (framework/analysis/iso9283.hpp) on simulated repeats: four commanded
// configurations of the UR5 measured five times each, with a known bias per configuration and
// known scatter; the figures against the standard's formulas evaluated here directly.

#include <gtest/gtest.h>

#include <cmath>

#include "kincal/framework/analysis/iso9283.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/workflows/validate.hpp"
#include "kincal/models/presets.hpp"

namespace kincal {
namespace {

TEST(Iso9283, PoseAndDistanceFiguresFollowTheStandardsFormulas) {
  const auto model = make_preset("ur5-urdf");
  const VectorXd values = model->parameters().nominal_values();
  VectorXd home(6);
  model->mechanism().home_actuators(values, home);
  const int configurations = 4, repeats = 5;
  Measurements data;
  data.actuators.resize(configurations * repeats + 1, 6);
  data.readings.resize(configurations * repeats + 1, 3);
  std::vector<Vector3d> predicted(configurations), bias(configurations);
  std::vector<std::vector<Vector3d>> measured(configurations);
  auto ws = model->make_workspace();
  VectorXd y(3);
  Random rng(12);
  int row = 0;
  for (int j = 0; j < repeats; ++j)  // cycle by cycle, as a test programme runs them
    for (int c = 0; c < configurations; ++c) {
      VectorXd q = home;
      for (int i = 0; i < 6; ++i) q[i] += 0.3 * std::sin(1.3 * c + 0.7 * i);
      model->predict(values, q, y, nullptr, ws);
      predicted[static_cast<std::size_t>(c)] = y;
      if (j == 0) bias[static_cast<std::size_t>(c)] = Vector3d(0.1 * c, -0.05, 0.02 * c);
      const Vector3d e(rng.symmetric(0.03), rng.symmetric(0.03), rng.symmetric(0.03));
      const Vector3d p = y + bias[static_cast<std::size_t>(c)] + e;
      measured[static_cast<std::size_t>(c)].push_back(p);
      data.actuators.row(row) = q.transpose();
      data.readings.row(row) = p.transpose();
      ++row;
    }
  // One configuration measured once: no statistics of its own.
  data.actuators.row(row) = (home.array() + 0.05).matrix().transpose();
  data.readings.row(row) = Vector3d(1, 2, 3).transpose();

  const Iso9283Stats stats = iso9283_statistics(*model, values, data);
  ASSERT_EQ(stats.poses.size(), 4u);
  for (int c = 0; c < configurations; ++c) {
    Vector3d bar = Vector3d::Zero();
    for (const Vector3d& p : measured[static_cast<std::size_t>(c)]) bar += p / repeats;
    double l_mean = 0, l_var = 0;
    for (const Vector3d& p : measured[static_cast<std::size_t>(c)])
      l_mean += (p - bar).norm() / repeats;
    for (const Vector3d& p : measured[static_cast<std::size_t>(c)])
      l_var += std::pow((p - bar).norm() - l_mean, 2) / (repeats - 1);
    const Iso9283Pose& pose = stats.poses[static_cast<std::size_t>(c)];
    EXPECT_EQ(pose.repeats, repeats);
    EXPECT_EQ(pose.first_row, c);
    EXPECT_NEAR(pose.accuracy, (bar - predicted[static_cast<std::size_t>(c)]).norm(), 1e-12);
    EXPECT_NEAR(pose.repeatability, l_mean + 3 * std::sqrt(l_var), 1e-12);
    // The bias is what accuracy sees, to the scatter's size.
    EXPECT_NEAR(pose.accuracy, bias[static_cast<std::size_t>(c)].norm(), 0.03);
  }
  ASSERT_EQ(stats.distances.size(), 3u);
  for (int a = 0; a + 1 < configurations; ++a) {
    const auto& m1 = measured[static_cast<std::size_t>(a)];
    const auto& m2 = measured[static_cast<std::size_t>(a + 1)];
    const double dc =
        (predicted[static_cast<std::size_t>(a)] - predicted[static_cast<std::size_t>(a + 1)])
            .norm();
    double mean = 0, var = 0;
    for (int j = 0; j < repeats; ++j) mean += (m1[j] - m2[j]).norm() / repeats;
    for (int j = 0; j < repeats; ++j)
      var += std::pow((m1[j] - m2[j]).norm() - mean, 2) / (repeats - 1);
    const Iso9283Distance& d = stats.distances[static_cast<std::size_t>(a)];
    EXPECT_NEAR(d.commanded, dc, 1e-12);
    EXPECT_NEAR(d.accuracy, mean - dc, 1e-12);
    EXPECT_NEAR(d.repeatability, 3 * std::sqrt(var), 1e-12);
  }
  const std::string text = iso9283_text(stats, {});
  EXPECT_NE(text.find("ISO 9283, 4 repeated configurations"), std::string::npos) << text;
  EXPECT_EQ(iso9283_json(stats, {})["poses"].size(), 4u);

  // The validate workflow reports them; data without repeats have none.
  ValidateRequest request;
  request.model = model;
  request.measurements.data = data;
  const ValidateResult result = validate(request);
  EXPECT_EQ(result.iso9283.poses.size(), 4u);
  Measurements once;
  once.actuators = data.actuators.topRows(configurations);
  once.readings = data.readings.topRows(configurations);
  EXPECT_FALSE(iso9283_statistics(*model, values, once).computed());
}

}  // namespace
}  // namespace kincal
