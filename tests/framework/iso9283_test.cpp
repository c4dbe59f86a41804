// ISO 9283 statistics (framework/analysis/iso9283.hpp) on simulated repeats: four commanded
// configurations of the UR5 measured five times each, with a known bias per configuration and
// known scatter; the figures against the standard's formulas evaluated here directly.

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>

#include "kincal/framework/analysis/iso9283.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/kinematics/pose.hpp"
#include "kincal/framework/report/pages.hpp"
#include "kincal/framework/workflows/validate.hpp"
#include "kincal/models/model_io.hpp"
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
  // The page for people has the section, the pairs' table included.
  const std::string html = report::validation_html(request, result, "", std::nullopt);
  EXPECT_NE(html.find(">ISO 9283 pose accuracy and repeatability<"), std::string::npos);
  EXPECT_NE(html.find("<th>AD (mm)</th>"), std::string::npos);
  Measurements once;
  once.actuators = data.actuators.topRows(configurations);
  once.readings = data.readings.topRows(configurations);
  EXPECT_FALSE(iso9283_statistics(*model, values, once).computed());
}

// A pose tracker's orientation: three configurations measured six times, each with a known
// bias rotation and a scatter; the mean orientation checked against the chordal mean of the
// quaternions (the principal eigenvector of sum q q^T, another method), AP(a, b, c) against
// log(mean R_c^T) and RP(a, b, c) against 3 x the sample std of log(R_j mean^T).
TEST(Iso9283, APoseTrackersOrientationAccuracyAndRepeatability) {
  nlohmann::ordered_json j = model_to_json(*make_preset("ur5-urdf"),
                                           make_preset("ur5-urdf")->parameters().nominal_values());
  const nlohmann::ordered_json identity = {{"position", {0, 0, 0}},
                                           {"rotation_zyx_deg", {0, 0, 0}}};
  j["sensors"] = nlohmann::ordered_json::array(
      {{{"type", "pose-tracker"}, {"name", "tracker"}, {"frame", identity}, {"marker", identity}}});
  const auto model = model_from_json(j, "ur5-pose.json");
  const VectorXd values = model->parameters().nominal_values();
  VectorXd home(6);
  model->mechanism().home_actuators(values, home);
  const int configurations = 3, repeats = 6;
  Measurements data;
  data.actuators.resize(configurations * repeats, 6);
  data.readings.resize(configurations * repeats, 6);
  std::vector<std::vector<Matrix3d>> measured(configurations);
  std::vector<Matrix3d> commanded(configurations);
  auto ws = model->make_workspace();
  VectorXd y(6);
  Random rng(5);
  int row = 0;
  for (int r = 0; r < repeats; ++r)
    for (int c = 0; c < configurations; ++c) {
      VectorXd q = home;
      for (int i = 0; i < 6; ++i) q[i] += 0.4 * std::sin(0.9 * c + 0.5 * i);
      ASSERT_TRUE(model->predict(values, q, y, nullptr, ws).ok());
      const Matrix3d Rc = exp_so3(y.segment<3>(3));
      commanded[static_cast<std::size_t>(c)] = Rc;
      const Vector3d bias(0.004 * (c + 1), -0.002, 0.003 * c);
      const Vector3d noise(rng.symmetric(5e-4), rng.symmetric(5e-4), rng.symmetric(5e-4));
      const Matrix3d R = exp_so3(bias) * exp_so3(noise) * Rc;
      measured[static_cast<std::size_t>(c)].push_back(R);
      data.actuators.row(row) = q.transpose();
      data.readings.row(row).head<3>() = y.head<3>().transpose();
      data.readings.row(row).segment<3>(3) = log_so3(R).transpose();
      ++row;
    }
  const Iso9283Stats stats = iso9283_statistics(*model, values, data);
  ASSERT_TRUE(stats.has_orientation);
  ASSERT_EQ(stats.poses.size(), 3u);
  for (int c = 0; c < configurations; ++c) {
    const auto& Rs = measured[static_cast<std::size_t>(c)];
    Eigen::Matrix4d M = Eigen::Matrix4d::Zero();
    for (const Matrix3d& R : Rs) {
      Eigen::Quaterniond q(R);
      if (q.w() < 0) q.coeffs() *= -1;
      M += q.coeffs() * q.coeffs().transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(M);
    const Eigen::Vector4d v = eig.eigenvectors().col(3);
    const Matrix3d mean =
        Eigen::Quaterniond(v[3], v[0], v[1], v[2]).normalized().toRotationMatrix();
    const Vector3d ap = log_so3(mean * commanded[static_cast<std::size_t>(c)].transpose());
    Vector3d squares = Vector3d::Zero();
    for (const Matrix3d& R : Rs) squares += log_so3(R * mean.transpose()).cwiseAbs2();
    const Vector3d rp = 3 * (squares / (repeats - 1)).cwiseSqrt();
    const Iso9283Pose& pose = stats.poses[static_cast<std::size_t>(c)];
    ASSERT_TRUE(pose.has_orientation);
    EXPECT_LT((pose.orientation_accuracy - ap).norm(), 1e-8) << c;
    EXPECT_LT((pose.orientation_repeatability - rp).norm(), 1e-8) << c;
    // The bias is what accuracy sees, to the scatter's size.
    EXPECT_LT((pose.orientation_accuracy - Vector3d(0.004 * (c + 1), -0.002, 0.003 * c)).norm(),
              1e-3);
  }
  const std::string text = iso9283_text(stats, {});
  EXPECT_NE(text.find("orientation accuracy |APa,b,c| max"), std::string::npos) << text;
  const auto json = iso9283_json(stats, {});
  EXPECT_EQ(json["poses"][0]["rp_abc_rad"].size(), 3u);
  EXPECT_TRUE(json.contains("max_ap_orientation_rad"));
  ValidateRequest request;
  request.model = model;
  request.measurements.data = data;
  const std::string html = report::validation_html(request, validate(request), "", std::nullopt);
  EXPECT_NE(html.find("<th>RPa</th>"), std::string::npos);
}

}  // namespace
}  // namespace kincal
