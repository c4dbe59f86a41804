// Kinematics of the 6-UPS hexapod: IK/FK round trip, honest FK failure, and every analytic
// Jacobian against central finite differences.

#include "kincal/models/hexapod.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "jacobian_check.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/models/presets.hpp"

namespace kincal {
namespace {

using kincal::testing::jacobians_match;
using kincal::testing::numerical_jacobian;

struct Fixture {
  std::shared_ptr<MeasurementModel> model = make_cube_hexapod();
  const Mechanism& mechanism = model->mechanism();
  const auto& hexapod() const { return dynamic_cast<const ClosedChainMechanism<6>&>(mechanism); }
  VectorXd params = model->parameters().nominal_values().head(mechanism.num_parameters());
};

// A pose near home: +-30 mm and +-0.1 rad.
Pose random_pose(Random& rng, const Pose& home) {
  Vector6d delta;
  for (int i = 0; i < 3; ++i) delta[i] = rng.symmetric(30.0);
  for (int i = 3; i < 6; ++i) delta[i] = rng.symmetric(0.1);
  return perturb(home, delta);
}

TEST(Hexapod, HomePoseIsTheCube) {
  Fixture f;
  VectorXd q(6);
  f.mechanism.inverse_kinematics(f.params, f.mechanism.home_pose(), q);
  // Legs 1-5 are axis-aligned and 354 mm long at home; leg 6 runs from (0,-205,280) to (0,177,270).
  for (int leg = 0; leg < 5; ++leg) EXPECT_NEAR(q[leg], 354.0, 1e-12) << "leg " << leg + 1;
  EXPECT_NEAR(q[5], std::sqrt(382.0 * 382.0 + 10.0 * 10.0), 1e-12);
}

TEST(Hexapod, ForwardKinematicsInvertsInverseKinematics) {
  Fixture f;
  Random rng(42);
  VectorXd q(6);
  for (int trial = 0; trial < 500; ++trial) {
    const Pose pose = random_pose(rng, f.mechanism.home_pose());
    f.mechanism.inverse_kinematics(f.params, pose, q);
    const ForwardKinematicsResult fk =
        f.mechanism.forward_kinematics(f.params, q, f.mechanism.home_pose());
    ASSERT_TRUE(fk.ok()) << "trial " << trial << ": " << fk.describe();
    EXPECT_LT(position_error(pose, fk.pose), 1e-9) << "trial " << trial;
    EXPECT_LT(log_so3(pose.rotation.transpose() * fk.pose.rotation).norm(), 1e-9)
        << "trial " << trial;
  }
}

TEST(Hexapod, StepGainBelowOneStillConverges) {
  Fixture f;
  Random rng(7);
  const Pose pose = random_pose(rng, f.mechanism.home_pose());
  VectorXd q(6);
  f.mechanism.inverse_kinematics(f.params, pose, q);
  ForwardKinematicsOptions options;
  options.step_gain = 0.5;
  options.max_iterations = 200;
  const auto fk = f.mechanism.forward_kinematics(f.params, q, f.mechanism.home_pose(), options);
  ASSERT_TRUE(fk.ok()) << fk.describe();
  EXPECT_GT(fk.iterations, 10);  // linear, not quadratic, convergence with k = 0.5
  EXPECT_LT(position_error(pose, fk.pose), 1e-9);
}

TEST(Hexapod, ForwardKinematicsReportsUnreachableLegLengths) {
  Fixture f;
  VectorXd q = VectorXd::Constant(6, 354.0);
  q[0] = -10.0;  // negative leg length
  auto fk = f.mechanism.forward_kinematics(f.params, q, f.mechanism.home_pose());
  EXPECT_EQ(fk.status, ForwardKinematicsStatus::kInvalidActuators);
  EXPECT_FALSE(fk.ok());

  // Leg 1 far longer than the others can follow: no pose satisfies all six constraints.
  q = VectorXd::Constant(6, 354.0);
  q[0] = 5000.0;
  fk = f.mechanism.forward_kinematics(f.params, q, f.mechanism.home_pose());
  EXPECT_FALSE(fk.ok()) << "returned a pose for unreachable legs";
  EXPECT_FALSE(fk.describe().empty());

  q = VectorXd::Constant(6, std::numeric_limits<double>::quiet_NaN());
  fk = f.mechanism.forward_kinematics(f.params, q, f.mechanism.home_pose());
  EXPECT_FALSE(fk.ok());
}

TEST(Hexapod, ForwardKinematicsStartedAtASingularSolutionReportsIt) {
  // Six vertical legs: nothing resists a horizontal shift of the platform. Started exactly
  // at the solution, the residuals are zero but the pose has no Jacobian: singular, not a
  // converged NaN pose.
  HexapodGeometry g;
  for (int leg = 0; leg < 6; ++leg) {
    const double angle = leg * 1.0471975511965976;
    g.base_joints[leg] = Vector3d(200 * std::cos(angle), 200 * std::sin(angle), 0);
    g.platform_joints[leg] = g.base_joints[leg];
  }
  g.home.translation = Vector3d(0, 0, 300);
  const Hexapod hexapod(g);
  VectorXd params(hexapod.num_parameters());
  for (int i = 0; i < params.size(); ++i) params[i] = hexapod.parameters()[i].nominal;
  VectorXd q(6);
  ASSERT_TRUE(hexapod.inverse_kinematics(params, hexapod.home_pose(), q).ok());
  const auto fk = hexapod.forward_kinematics(params, q, hexapod.home_pose());
  EXPECT_EQ(fk.status, ForwardKinematicsStatus::kSingular) << fk.describe();
  EXPECT_TRUE(fk.pose.translation.allFinite() && fk.pose.rotation.allFinite());
}

TEST(Hexapod, Stewart66PresetIsAGeneral66PlatformAtZeroStrokeAtHome) {
  const auto model = make_stewart_6_6();
  const auto& hexapod = dynamic_cast<const Hexapod&>(model->mechanism());
  const VectorXd params = model->parameters().nominal_values().head(hexapod.num_parameters());
  const HexapodGeometry g = hexapod.geometry_from(params);
  for (int i = 0; i < 6; ++i) {
    // Joints on circles of radius 325 (base) and 125 mm (platform), Table 1's rounding.
    EXPECT_NEAR(g.base_joints[i].head<2>().norm(), 325.0, 1e-3) << "leg " << i + 1;
    EXPECT_NEAR(g.platform_joints[i].head<2>().norm(), 125.0, 1e-3) << "leg " << i + 1;
    EXPECT_EQ(g.leg_offsets[i], 604.8652);
    // 6-6: no two joints of a platform coincide.
    for (int j = 0; j < i; ++j) {
      EXPECT_GT((g.base_joints[i] - g.base_joints[j]).norm(), 100.0);
      EXPECT_GT((g.platform_joints[i] - g.platform_joints[j]).norm(), 30.0);
    }
  }
  // At home every leg is at its offset length: zero stroke, to Table 1's rounding.
  VectorXd q(6);
  ASSERT_TRUE(hexapod.home_actuators(params, q).ok());
  EXPECT_LT(q.cwiseAbs().maxCoeff(), 1e-4) << q.transpose();
  const auto fk = hexapod.forward_kinematics(params, VectorXd::Zero(6), hexapod.home_pose());
  ASSERT_TRUE(fk.ok()) << fk.describe();
  EXPECT_LT(position_error(fk.pose, hexapod.home_pose()), 1e-3);
}

TEST(Hexapod, ConstraintJacobianWrtPoseMatchesFiniteDifferences) {
  Fixture f;
  Random rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    const Pose pose = random_pose(rng, f.mechanism.home_pose());
    VectorXd q(6);
    f.mechanism.inverse_kinematics(f.params, random_pose(rng, f.mechanism.home_pose()), q);
    Vector6d g;
    Matrix6d J;
    f.hexapod().constraints(f.params, q, pose, g, &J);
    auto constraint_at = [&](const VectorXd& delta) {
      Vector6d out;
      f.hexapod().constraints(f.params, q, perturb(pose, delta), out, nullptr);
      return VectorXd(out);
    };
    EXPECT_TRUE(
        jacobians_match(J, numerical_jacobian(constraint_at, VectorXd::Zero(6), 1e-6), 1e-7));
  }
}

TEST(Hexapod, ConstraintJacobianWrtParamsMatchesFiniteDifferences) {
  Fixture f;
  Random rng(4);
  const Pose pose = random_pose(rng, f.mechanism.home_pose());
  VectorXd q(6);
  f.mechanism.inverse_kinematics(f.params, random_pose(rng, f.mechanism.home_pose()), q);
  Matrix6Xd J(6, f.params.size());
  f.hexapod().constraint_jacobian_params(f.params, q, pose, J);
  auto constraint_at = [&](const VectorXd& p) {
    Vector6d out;
    f.hexapod().constraints(p, q, pose, out, nullptr);
    return VectorXd(out);
  };
  EXPECT_TRUE(jacobians_match(J, numerical_jacobian(constraint_at, f.params, 1e-5), 1e-7,
                              f.model->parameters().names()));
}

TEST(Hexapod, PoseJacobianWrtParamsMatchesFiniteDifferencesOfForwardKinematics) {
  Fixture f;
  Random rng(5);
  for (int trial = 0; trial < 5; ++trial) {
    VectorXd q(6);
    f.mechanism.inverse_kinematics(f.params, random_pose(rng, f.mechanism.home_pose()), q);
    const auto fk = f.mechanism.forward_kinematics(f.params, q, f.mechanism.home_pose());
    ASSERT_TRUE(fk.ok());
    Matrix6Xd J(6, f.params.size());
    f.mechanism.pose_jacobian_params(f.params, q, fk.pose, J);
    // Pose difference expressed in the perturbation convention: [dt; log(R' R^T)].
    auto pose_delta_at = [&](const VectorXd& p) {
      const auto moved = f.mechanism.forward_kinematics(p, q, f.mechanism.home_pose());
      Vector6d d;
      d.head<3>() = moved.pose.translation - fk.pose.translation;
      d.tail<3>() = log_so3(moved.pose.rotation * fk.pose.rotation.transpose());
      return VectorXd(d);
    };
    EXPECT_TRUE(jacobians_match(J, numerical_jacobian(pose_delta_at, f.params, 1e-5), 1e-6,
                                f.model->parameters().names()))
        << "trial " << trial;
  }
}

TEST(Hexapod, SparseWeightedConstraintJacobianEqualsTheDenseProduct) {
  Fixture f;
  Random rng(8);
  const Pose pose = random_pose(rng, f.mechanism.home_pose());
  VectorXd q(6);
  f.mechanism.inverse_kinematics(f.params, random_pose(rng, f.mechanism.home_pose()), q);
  Matrix6Xd J_g_params(6, f.params.size());
  f.hexapod().constraint_jacobian_params(f.params, q, pose, J_g_params);
  Vector6d lambda;
  for (int i = 0; i < 6; ++i) lambda[i] = rng.symmetric(2.0);
  Eigen::RowVectorXd sparse = Eigen::RowVectorXd::Constant(f.params.size(), 1e300);
  f.hexapod().constraint_jacobian_params_left(f.params, q, pose, lambda, sparse);
  // The base class's dense default, for comparison.
  Eigen::RowVectorXd dense(f.params.size());
  f.hexapod().ClosedChainMechanism<6>::constraint_jacobian_params_left(f.params, q, pose, lambda,
                                                                       dense);
  EXPECT_TRUE(jacobians_match(sparse, lambda.transpose() * J_g_params, 1e-14));
  EXPECT_TRUE(jacobians_match(dense, lambda.transpose() * J_g_params, 1e-14));
}

TEST(Hexapod, AdjointOutputJacobianEqualsTheChainRule) {
  Fixture f;
  Random rng(9);
  for (int trial = 0; trial < 5; ++trial) {
    VectorXd q(6);
    f.mechanism.inverse_kinematics(f.params, random_pose(rng, f.mechanism.home_pose()), q);
    const auto fk = f.mechanism.forward_kinematics(f.params, q, f.mechanism.home_pose());
    ASSERT_TRUE(fk.ok());
    MatrixX6d J_out_pose(2, 6);
    for (int i = 0; i < J_out_pose.size(); ++i) J_out_pose.data()[i] = rng.symmetric(1.0);
    Matrix6Xd J_pose_params(6, f.params.size());
    f.mechanism.pose_jacobian_params(f.params, q, fk.pose, J_pose_params);
    MatrixXd adjoint(2, f.params.size()), chained(2, f.params.size());
    f.mechanism.output_jacobian_params(f.params, q, fk.pose, J_out_pose, adjoint);
    f.mechanism.Mechanism::output_jacobian_params(f.params, q, fk.pose, J_out_pose, chained);
    EXPECT_TRUE(jacobians_match(adjoint, J_out_pose * J_pose_params, 1e-12)) << "trial " << trial;
    EXPECT_TRUE(jacobians_match(chained, J_out_pose * J_pose_params, 1e-12)) << "trial " << trial;
  }
}

}  // namespace
}  // namespace kincal
