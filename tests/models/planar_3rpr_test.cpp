// Kinematics of the planar 3-RPR robot: known values, FK/IK round trip over the workspace,
// singular and invalid configurations as statuses, every analytic Jacobian against central
// finite differences, the sparse left product against the dense one, and its model file.

#include "kincal/models/planar_3rpr.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "jacobian_check.hpp"
#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/models/model_io.hpp"

namespace kincal {
namespace {

using kincal::testing::jacobians_match;
using kincal::testing::numerical_jacobian;

struct Fixture {
  std::shared_ptr<MeasurementModel> model = ModelRegistry::global().make_preset("planar-3rpr");
  const Planar3Rpr& robot() const { return dynamic_cast<const Planar3Rpr&>(model->mechanism()); }
  VectorXd params = model->parameters().nominal_values().head(robot().num_parameters());
};

// A planar pose near the preset's home: +-15 mm and +-0.05 rad, inside the region the
// default configuration box reaches and away from the singular curves.
PlanarPose random_planar_pose(Random& rng, const PlanarPose& home) {
  return {home.x + rng.symmetric(15.0), home.y + rng.symmetric(15.0),
          home.theta + rng.symmetric(0.05)};
}

// [dt; log(R1 R0^T)]: the SE(3) perturbation taking `from` to `to`.
Vector6d pose_difference(const Pose& from, const Pose& to) {
  Vector6d d;
  d << to.translation - from.translation, log_so3(to.rotation * from.rotation.transpose());
  return d;
}

// A geometry singular at pose (0, 0, 0): the three leg lines all pass through the point c,
// so the legs cannot resist a rotation of the platform about c.
Planar3RprGeometry concurrent_legs_geometry() {
  Planar3RprGeometry g;
  g.platform_joints = {Eigen::Vector2d(0, 0), Eigen::Vector2d(60, 0), Eigen::Vector2d(0, 60)};
  const Eigen::Vector2d c(20, 100);
  const double reach[3] = {2.5, 3.0, 4.0};  // base joints beyond the platform joints
  for (int leg = 0; leg < 3; ++leg)
    g.base_joints[leg] = c + reach[leg] * (g.platform_joints[leg] - c);
  g.home = {0, 0, 0};
  return g;
}

VectorXd nominal_values(const Planar3Rpr& robot) {
  VectorXd v(robot.num_parameters());
  for (int i = 0; i < v.size(); ++i) v[i] = robot.parameters()[i].nominal;
  return v;
}

TEST(Planar3Rpr, ParametersAndActuatorsAreNamedPerLegInMillimetres) {
  Fixture f;
  ASSERT_EQ(f.robot().num_parameters(), 15);
  EXPECT_EQ(f.robot().parameters()[0].name, "leg1.base.x");
  EXPECT_EQ(f.robot().parameters()[3].name, "leg1.platform.y");
  EXPECT_EQ(f.robot().parameters()[14].name, "leg3.offset");
  for (const auto& p : f.robot().parameters()) EXPECT_EQ(p.unit, "mm") << p.name;
  ASSERT_EQ(f.robot().num_actuators(), 3);
  EXPECT_EQ(f.robot().actuators()[1].name, "leg2");
  EXPECT_EQ(f.robot().actuators()[1].unit, "mm");
}

TEST(Planar3Rpr, InverseKinematicsKnownValues) {
  Fixture f;
  VectorXd q(3);
  // At (230, 180, 0), a pose the prototype's authors commanded: legs from (40, 20), (340, 0),
  // (0, 300) to (230, 180), (290, 180), (230, 240), less the 168.4 mm offsets.
  ASSERT_TRUE(f.robot().inverse_kinematics(f.params, to_pose({230, 180, 0}), q).ok());
  EXPECT_NEAR(q[0], std::hypot(190.0, 160.0) - 168.4, 1e-12);
  EXPECT_NEAR(q[1], std::hypot(-50.0, 180.0) - 168.4, 1e-12);
  EXPECT_NEAR(q[2], std::hypot(230.0, -60.0) - 168.4, 1e-12);
  // Turned by 90 degrees about z at (100, 100): platform joints at (100, 100), (100, 160),
  // (40, 100).
  ASSERT_TRUE(f.robot().inverse_kinematics(f.params, to_pose({100, 100, kPi / 2}), q).ok());
  EXPECT_NEAR(q[0], std::hypot(60.0, 80.0) - 168.4, 1e-12);
  EXPECT_NEAR(q[1], std::hypot(-240.0, 160.0) - 168.4, 1e-12);
  EXPECT_NEAR(q[2], std::hypot(40.0, -200.0) - 168.4, 1e-12);
  // Home (150, 180, -70 degrees): legs 194.2, 209.8 and 229.1 mm long, inside the
  // prototype's 170-265 mm stroke with the default 15 mm range on either side.
  ASSERT_TRUE(f.robot().home_actuators(f.params, q).ok());
  EXPECT_NEAR(q[0] + 168.4, 194.2, 0.05);
  EXPECT_NEAR(q[1] + 168.4, 209.8, 0.05);
  EXPECT_NEAR(q[2] + 168.4, 229.1, 0.05);
  for (int leg = 0; leg < 3; ++leg) {
    EXPECT_GE(q[leg] + 168.4 - Planar3Rpr::kDefaultLegRange, 170.0);
    EXPECT_LE(q[leg] + 168.4 + Planar3Rpr::kDefaultLegRange, 265.0);
  }
}

TEST(Planar3Rpr, PlanarPosesConvertBothWays) {
  const PlanarPose p{12.5, -3.0, 2.9};
  PlanarPose back;
  ASSERT_TRUE(to_planar_pose(to_pose(p), back));
  EXPECT_DOUBLE_EQ(back.x, 12.5);
  EXPECT_DOUBLE_EQ(back.y, -3.0);
  EXPECT_NEAR(back.theta, 2.9, 1e-15);
  Pose lifted = to_pose(p);
  lifted.translation.z() = 1e-3;
  EXPECT_FALSE(to_planar_pose(lifted, back));
  EXPECT_FALSE(
      to_planar_pose(perturb(to_pose(p), (Vector6d() << 0, 0, 0, 1e-3, 0, 0).finished()), back));
  // Upside down (a half turn about x) keeps z but is no planar pose.
  EXPECT_FALSE(
      to_planar_pose(perturb(to_pose(p), (Vector6d() << 0, 0, 0, kPi, 0, 0).finished()), back));
}

TEST(Planar3Rpr, ForwardKinematicsInvertsInverseKinematicsOverTheWorkspace) {
  Fixture f;
  PlanarPose home;
  ASSERT_TRUE(to_planar_pose(f.robot().home_pose(), home));
  Random rng(42);
  VectorXd q(3);
  for (int trial = 0; trial < 500; ++trial) {
    const Pose pose = to_pose(random_planar_pose(rng, home));
    ASSERT_TRUE(f.robot().inverse_kinematics(f.params, pose, q).ok());
    const ForwardKinematicsResult fk =
        f.robot().forward_kinematics(f.params, q, f.robot().home_pose());
    ASSERT_TRUE(fk.ok()) << "trial " << trial << ": " << fk.describe();
    EXPECT_LT(pose_difference(pose, fk.pose).norm(), 1e-9) << "trial " << trial;
    // The pose never leaves the plane.
    EXPECT_EQ(fk.pose.translation.z(), 0.0);
    EXPECT_EQ(fk.pose.rotation(2, 2), 1.0);
  }
}

TEST(Planar3Rpr, SingularConfigurationIsAStatus) {
  const Planar3Rpr robot(concurrent_legs_geometry());
  const VectorXd params = nominal_values(robot);
  VectorXd q(3);
  ASSERT_TRUE(robot.inverse_kinematics(params, robot.home_pose(), q).ok());
  Planar3Rpr::ConstraintVector g;
  Planar3Rpr::ConstraintJacobian J;
  robot.constraints(params, q, robot.home_pose(), g, &J);
  EXPECT_LT(std::abs(J.determinant()), 1e-9 * J.norm() * J.norm() * J.norm());
  // Started exactly at the singular solution: converged residuals, but no pose Jacobian.
  ForwardKinematicsResult fk = robot.forward_kinematics(params, q, robot.home_pose());
  EXPECT_EQ(fk.status, ForwardKinematicsStatus::kSingular) << fk.describe();
  EXPECT_FALSE(fk.ok());
  // Started nearby, Newton heads for a double root: whatever it reports, never a NaN pose,
  // and a converged pose closes the loops.
  fk = robot.forward_kinematics(params, q, to_pose({1.0, -1.0, 0.01}));
  EXPECT_TRUE(fk.pose.translation.allFinite() && fk.pose.rotation.allFinite()) << fk.describe();
  if (fk.ok()) {
    robot.constraints(params, q, fk.pose, g, nullptr);
    EXPECT_LT(g.cwiseAbs().maxCoeff(), 1e-9) << fk.describe();
  }
}

TEST(Planar3Rpr, ForwardKinematicsReportsInvalidAndUnreachableLegs) {
  Fixture f;
  VectorXd q(3);
  ASSERT_TRUE(f.robot().inverse_kinematics(f.params, f.robot().home_pose(), q).ok());
  VectorXd bad = q;
  bad[0] = -200.0;  // 168.4 + (-200) < 0: a negative leg
  auto fk = f.robot().forward_kinematics(f.params, bad, f.robot().home_pose());
  EXPECT_EQ(fk.status, ForwardKinematicsStatus::kInvalidActuators);
  bad = q;
  bad[2] = std::numeric_limits<double>::quiet_NaN();
  fk = f.robot().forward_kinematics(f.params, bad, f.robot().home_pose());
  EXPECT_EQ(fk.status, ForwardKinematicsStatus::kInvalidActuators);
  EXPECT_FALSE(f.robot().actuators_valid(f.params, VectorXd::Zero(2)));
  // Leg 1 far longer than the others allow: no pose closes the three loops.
  bad = q;
  bad[0] = 5000.0;
  fk = f.robot().forward_kinematics(f.params, bad, f.robot().home_pose());
  EXPECT_FALSE(fk.ok()) << "returned a pose for unreachable legs";
  EXPECT_FALSE(fk.describe().empty());
}

TEST(Planar3Rpr, InverseKinematicsReportsPosesItCannotReach) {
  Fixture f;
  VectorXd q(3);
  Pose off_plane = f.robot().home_pose();
  off_plane.translation.z() = 2.0;
  auto ik = f.robot().inverse_kinematics(f.params, off_plane, q);
  EXPECT_EQ(ik.status, InverseKinematicsStatus::kUnreachable);
  EXPECT_NE(ik.describe().find("plane"), std::string::npos) << ik.describe();

  const Pose tilted = perturb(f.robot().home_pose(), (Vector6d() << 0, 0, 0, 0, 0.1, 0).finished());
  EXPECT_EQ(f.robot().inverse_kinematics(f.params, tilted, q).status,
            InverseKinematicsStatus::kUnreachable);

  // The platform joint of leg 1 on its base joint.
  ik = f.robot().inverse_kinematics(f.params, to_pose({40, 20, 0}), q);
  EXPECT_EQ(ik.status, InverseKinematicsStatus::kUnreachable);
  EXPECT_NE(ik.describe().find("leg 1"), std::string::npos) << ik.describe();

  Pose nan_pose = f.robot().home_pose();
  nan_pose.translation.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(f.robot().inverse_kinematics(f.params, nan_pose, q).status,
            InverseKinematicsStatus::kNonFinite);
}

TEST(Planar3Rpr, MotionBasisSpansThePlanarMotions) {
  const auto E = Planar3Rpr::planar_motion_basis();
  Planar3Rpr::MotionBasis expected = Planar3Rpr::MotionBasis::Zero();
  expected(0, 0) = expected(1, 1) = expected(5, 2) = 1;
  EXPECT_EQ(E, expected);
  Fixture f;
  EXPECT_EQ(f.robot().motion_basis(), expected);
}

TEST(Planar3Rpr, ConstraintJacobianWrtPoseMatchesFiniteDifferences) {
  Fixture f;
  PlanarPose home;
  ASSERT_TRUE(to_planar_pose(f.robot().home_pose(), home));
  Random rng(3);
  const auto E = f.robot().motion_basis();
  for (int trial = 0; trial < 20; ++trial) {
    const Pose pose = to_pose(random_planar_pose(rng, home));
    VectorXd q(3);
    ASSERT_TRUE(
        f.robot().inverse_kinematics(f.params, to_pose(random_planar_pose(rng, home)), q).ok());
    Planar3Rpr::ConstraintVector g;
    Planar3Rpr::ConstraintJacobian J;
    f.robot().constraints(f.params, q, pose, g, &J);
    // Local coordinates (dx, dy, dtheta), mapped to SE(3) by the motion basis.
    auto constraint_at = [&](const VectorXd& local) {
      Planar3Rpr::ConstraintVector out;
      f.robot().constraints(f.params, q, perturb(pose, E * local), out, nullptr);
      return VectorXd(out);
    };
    EXPECT_TRUE(
        jacobians_match(J, numerical_jacobian(constraint_at, VectorXd::Zero(3), 1e-6), 1e-7))
        << "trial " << trial;
  }
}

TEST(Planar3Rpr, ConstraintJacobianWrtParamsMatchesFiniteDifferences) {
  Fixture f;
  PlanarPose home;
  ASSERT_TRUE(to_planar_pose(f.robot().home_pose(), home));
  Random rng(4);
  for (int trial = 0; trial < 5; ++trial) {
    const Pose pose = to_pose(random_planar_pose(rng, home));
    VectorXd q(3);
    ASSERT_TRUE(
        f.robot().inverse_kinematics(f.params, to_pose(random_planar_pose(rng, home)), q).ok());
    Planar3Rpr::ParamsJacobian J(3, f.params.size());
    f.robot().constraint_jacobian_params(f.params, q, pose, J);
    auto constraint_at = [&](const VectorXd& p) {
      Planar3Rpr::ConstraintVector out;
      f.robot().constraints(p, q, pose, out, nullptr);
      return VectorXd(out);
    };
    EXPECT_TRUE(jacobians_match(J, numerical_jacobian(constraint_at, f.params, 1e-5), 1e-7,
                                f.model->parameters().names()))
        << "trial " << trial;
  }
}

TEST(Planar3Rpr, PoseJacobianWrtParamsMatchesFiniteDifferencesOfForwardKinematics) {
  Fixture f;
  PlanarPose home;
  ASSERT_TRUE(to_planar_pose(f.robot().home_pose(), home));
  Random rng(5);
  for (int trial = 0; trial < 5; ++trial) {
    VectorXd q(3);
    ASSERT_TRUE(
        f.robot().inverse_kinematics(f.params, to_pose(random_planar_pose(rng, home)), q).ok());
    const auto fk = f.robot().forward_kinematics(f.params, q, f.robot().home_pose());
    ASSERT_TRUE(fk.ok()) << fk.describe();
    Matrix6Xd J(6, f.params.size());
    f.robot().pose_jacobian_params(f.params, q, fk.pose, J);
    auto pose_delta_at = [&](const VectorXd& p) {
      const auto moved = f.robot().forward_kinematics(p, q, f.robot().home_pose());
      EXPECT_TRUE(moved.ok()) << moved.describe();
      return VectorXd(pose_difference(fk.pose, moved.pose));
    };
    EXPECT_TRUE(jacobians_match(J, numerical_jacobian(pose_delta_at, f.params, 1e-5), 1e-6,
                                f.model->parameters().names()))
        << "trial " << trial;
    // Parameters move the platform within the plane only: no z, no tilt.
    EXPECT_EQ(J.row(2).norm() + J.row(3).norm() + J.row(4).norm(), 0.0);
  }
}

TEST(Planar3Rpr, SparseWeightedConstraintJacobianEqualsTheDenseProduct) {
  Fixture f;
  PlanarPose home;
  ASSERT_TRUE(to_planar_pose(f.robot().home_pose(), home));
  Random rng(8);
  const Pose pose = to_pose(random_planar_pose(rng, home));
  VectorXd q(3);
  ASSERT_TRUE(
      f.robot().inverse_kinematics(f.params, to_pose(random_planar_pose(rng, home)), q).ok());
  Planar3Rpr::ParamsJacobian J_g_params(3, f.params.size());
  f.robot().constraint_jacobian_params(f.params, q, pose, J_g_params);
  Planar3Rpr::ConstraintVector lambda;
  for (int i = 0; i < 3; ++i) lambda[i] = rng.symmetric(2.0);
  Eigen::RowVectorXd sparse = Eigen::RowVectorXd::Constant(f.params.size(), 1e300);
  f.robot().constraint_jacobian_params_left(f.params, q, pose, lambda, sparse);
  // The base class's dense default, for comparison.
  Eigen::RowVectorXd dense(f.params.size());
  f.robot().ClosedChainMechanism<3>::constraint_jacobian_params_left(f.params, q, pose, lambda,
                                                                     dense);
  EXPECT_TRUE(jacobians_match(sparse, lambda.transpose() * J_g_params, 1e-14));
  EXPECT_TRUE(jacobians_match(dense, lambda.transpose() * J_g_params, 1e-14));
}

TEST(Planar3Rpr, AdjointOutputJacobianEqualsTheChainRule) {
  Fixture f;
  PlanarPose home;
  ASSERT_TRUE(to_planar_pose(f.robot().home_pose(), home));
  Random rng(9);
  for (int trial = 0; trial < 5; ++trial) {
    VectorXd q(3);
    ASSERT_TRUE(
        f.robot().inverse_kinematics(f.params, to_pose(random_planar_pose(rng, home)), q).ok());
    const auto fk = f.robot().forward_kinematics(f.params, q, f.robot().home_pose());
    ASSERT_TRUE(fk.ok());
    MatrixX6d J_out_pose(2, 6);
    for (int i = 0; i < J_out_pose.size(); ++i) J_out_pose.data()[i] = rng.symmetric(1.0);
    Matrix6Xd J_pose_params(6, f.params.size());
    f.robot().pose_jacobian_params(f.params, q, fk.pose, J_pose_params);
    MatrixXd adjoint(2, f.params.size()), chained(2, f.params.size());
    f.robot().output_jacobian_params(f.params, q, fk.pose, J_out_pose, adjoint);
    f.robot().Mechanism::output_jacobian_params(f.params, q, fk.pose, J_out_pose, chained);
    EXPECT_TRUE(jacobians_match(adjoint, J_out_pose * J_pose_params, 1e-12)) << "trial " << trial;
    EXPECT_TRUE(jacobians_match(chained, J_out_pose * J_pose_params, 1e-12)) << "trial " << trial;
  }
}

TEST(Planar3Rpr, ModelFileSaysWhereItIsWrong) {
  Fixture f;
  const Json good = model_to_json(*f.model, f.model->parameters().nominal_values());
  ASSERT_EQ(good["mechanism"]["type"], "planar-3rpr");
  EXPECT_EQ(good["mechanism"]["legs"][1]["base"], Json::array({340.0, 0.0}));

  auto expect_error = [](Json j, const std::string& fragment) {
    try {
      model_from_json(j, "robot.json");
      ADD_FAILURE() << "no error, expected one with '" << fragment << "'";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("robot.json"), std::string::npos) << e.what();
    }
  };
  Json j = good;
  j["mechanism"]["legs"][1]["base"] = Json::array({340.0, 0.0, 0.0});
  expect_error(j, "mechanism.legs[1].base");
  j = good;
  j["mechanism"]["legs"].erase(2);
  expect_error(j, "mechanism.legs");
  j = good;
  j["mechanism"]["home_pose"] = {{"position", Json::array({1.0, 2.0})}, {"theta", 0.0}};
  expect_error(j, "mechanism.home_pose");
  j = good;
  j["mechanism"]["legs"][0]["name"] = "leg2";
  expect_error(j, "mechanism.legs[0].name");
}

}  // namespace
}  // namespace kincal
