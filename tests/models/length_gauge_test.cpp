#include "kincal/models/length_gauge.hpp"

#include <gtest/gtest.h>

#include "jacobian_check.hpp"
#include "kincal/framework/base/random.hpp"

namespace kincal {
namespace {

using kincal::testing::jacobians_match;
using kincal::testing::numerical_jacobian;

TEST(LengthGauge, ReadsDistancePlusOffset) {
  LengthGauge gauge("gauge", Vector3d(0, 0, 0), Vector3d(3, 4, 0), 0.5);
  const VectorXd params = VectorXd::Map(std::vector<double>{0, 0, 0, 3, 4, 0, 0.5}.data(), 7);
  VectorXd reading(1);
  gauge.predict(params, Pose{}, reading, nullptr, nullptr);
  EXPECT_DOUBLE_EQ(reading[0], 5.5);
}

TEST(LengthGauge, JacobiansMatchFiniteDifferences) {
  LengthGauge gauge("gauge", Vector3d(-200, 500, 500), Vector3d(-200, 205, -5), 1.5);
  VectorXd params(7);
  params << -200, 500, 500, -200, 205, -5, 1.5;
  Random rng(11);
  for (int trial = 0; trial < 10; ++trial) {
    Vector6d delta;
    for (int i = 0; i < 6; ++i) delta[i] = rng.symmetric(i < 3 ? 50.0 : 0.2);
    Pose pose = perturb(Pose{Matrix3d::Identity(), Vector3d(0, 0, 410)}, delta);
    VectorXd reading(1);
    MatrixXd J_pose(1, 6), J_params(1, 7);
    gauge.predict(params, pose, reading, &J_pose, &J_params);
    auto by_pose = [&](const VectorXd& d) {
      VectorXd r(1);
      gauge.predict(params, perturb(pose, d), r, nullptr, nullptr);
      return r;
    };
    auto by_params = [&](const VectorXd& p) {
      VectorXd r(1);
      gauge.predict(p, pose, r, nullptr, nullptr);
      return r;
    };
    EXPECT_TRUE(
        jacobians_match(J_pose, numerical_jacobian(by_pose, VectorXd::Zero(6), 1e-6), 1e-7));
    EXPECT_TRUE(jacobians_match(J_params, numerical_jacobian(by_params, params, 1e-5), 1e-7));
  }
}

}  // namespace
}  // namespace kincal
