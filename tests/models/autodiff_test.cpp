// Automatic derivatives (framework/kinematics/autodiff.hpp) through the twins of the length gauge,
// the hexapod and the serial arm (autodiff_twins.hpp): every Jacobian the interfaces need must
// equal the hand-written type's to rounding and pass the same finite-difference checks as the
// conformance suite (model_conformance_test.cpp), and a calibration on the twin must land
// where the hand-written model's does.

#include <gtest/gtest.h>

#include "autodiff_twins.hpp"
#include "jacobian_check.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/presets.hpp"
#include "kincal/models/serial_arm_presets.hpp"

namespace kincal {
namespace {

using kincal::testing::autodiff_twin;
using kincal::testing::jacobians_match;
using kincal::testing::numerical_jacobian;

Vector6d pose_difference(const Pose& from, const Pose& to) {
  Vector6d d;
  d << to.translation - from.translation, log_so3(to.rotation * from.rotation.transpose());
  return d;
}

struct Twins {
  std::shared_ptr<MeasurementModel> hand, twin;
  Scenario scenario;  // drawn with the hand-written model
};

Twins twins_of(const std::shared_ptr<MeasurementModel>& hand, std::uint64_t seed) {
  ScenarioOptions options;
  options.num_configurations = 6;
  options.num_validation = 0;
  options.seed = seed;
  return {hand, autodiff_twin(*hand), make_scenario(hand, options)};
}

std::vector<std::shared_ptr<MeasurementModel>> hand_models() {
  return {make_cube_hexapod(), make_stewart_6_6(), make_puma560(), make_ur5()};
}

TEST(AutoDiff, TwinsReplaceTheMechanismAndTheGauges) {
  const auto hexapod = autodiff_twin(*make_cube_hexapod());
  EXPECT_EQ(hexapod->mechanism().type(), "hexapod-6ups-autodiff");
  EXPECT_EQ(hexapod->sensors()[0]->type(), "length-gauge-autodiff");
  EXPECT_EQ(autodiff_twin(*make_puma560())->mechanism().type(), "serial-arm-autodiff");
}

TEST(AutoDiff, ForwardKinematicsAndPoseJacobianEqualTheHandWrittenOnes) {
  for (const auto& model : hand_models()) {
    const Twins t = twins_of(model, 11);
    const Mechanism &hand = t.hand->mechanism(), &twin = t.twin->mechanism();
    SCOPED_TRACE(hand.type());
    const VectorXd params = t.scenario.truth.head(hand.num_parameters());
    const auto options = t.hand->forward_kinematics_options();
    for (int j = 0; j < t.scenario.calibration.size(); ++j) {
      const VectorXd q = t.scenario.calibration.actuators.row(j).transpose();
      const auto a = hand.forward_kinematics(params, q, hand.home_pose(), options);
      const auto b = twin.forward_kinematics(params, q, twin.home_pose(), options);
      ASSERT_TRUE(a.ok() && b.ok()) << a.describe() << " / " << b.describe();
      EXPECT_LT(pose_difference(a.pose, b.pose).norm(), 1e-9) << "configuration " << j;
      Matrix6Xd J_hand(6, hand.num_parameters()), J_twin(6, hand.num_parameters());
      hand.pose_jacobian_params(params, q, a.pose, J_hand);
      twin.pose_jacobian_params(params, q, a.pose, J_twin);
      EXPECT_TRUE(jacobians_match(J_twin, J_hand, 1e-10, t.hand->parameters().names()))
          << "configuration " << j;
    }
  }
}

TEST(AutoDiff, PoseJacobianMatchesFiniteDifferences) {
  for (const auto& model : hand_models()) {
    const Twins t = twins_of(model, 12);
    const Mechanism& twin = t.twin->mechanism();
    SCOPED_TRACE(twin.type());
    const VectorXd params = t.scenario.truth.head(twin.num_parameters());
    const auto options = t.twin->forward_kinematics_options();
    for (int j = 0; j < 3; ++j) {
      const VectorXd q = t.scenario.calibration.actuators.row(j).transpose();
      const auto fk = twin.forward_kinematics(params, q, twin.home_pose(), options);
      ASSERT_TRUE(fk.ok()) << fk.describe();
      Matrix6Xd J(6, twin.num_parameters());
      twin.pose_jacobian_params(params, q, fk.pose, J);
      auto pose_at = [&](const VectorXd& p) -> VectorXd {
        const auto moved = twin.forward_kinematics(p, q, twin.home_pose(), options);
        EXPECT_TRUE(moved.ok()) << moved.describe();
        return pose_difference(fk.pose, moved.pose);
      };
      EXPECT_TRUE(jacobians_match(J, numerical_jacobian(pose_at, params, 1e-6), 1e-6,
                                  t.twin->parameters().names()))
          << "configuration " << j;
    }
  }
}

TEST(AutoDiff, ClosedChainConstraintJacobiansEqualTheHandWrittenOnes) {
  const Twins t = twins_of(make_cube_hexapod(), 13);
  const auto& hand = static_cast<const Hexapod&>(t.hand->mechanism());
  const auto& twin = static_cast<const testing::AutoDiffHexapod&>(t.twin->mechanism());
  const VectorXd params = t.scenario.truth.head(hand.num_parameters());
  for (int j = 0; j < t.scenario.calibration.size(); ++j) {
    const VectorXd q = t.scenario.calibration.actuators.row(j).transpose();
    // Off the solution on purpose: the constraints are not zero there.
    const Pose pose = perturb(hand.home_pose(), Vector6d::Constant(0.01 * (j + 1)));
    Vector6d g_hand, g_twin;
    Matrix6d Jp_hand, Jp_twin;
    hand.constraints(params, q, pose, g_hand, &Jp_hand);
    twin.constraints(params, q, pose, g_twin, &Jp_twin);
    EXPECT_LT((g_hand - g_twin).cwiseAbs().maxCoeff(), 1e-10);
    twin.constraints(params, q, pose, g_twin, nullptr);
    EXPECT_LT((g_hand - g_twin).cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_TRUE(jacobians_match(Jp_twin, Jp_hand, 1e-12));
    Matrix6Xd Jq_hand(6, hand.num_parameters()), Jq_twin(6, hand.num_parameters());
    hand.constraint_jacobian_params(params, q, pose, Jq_hand);
    twin.constraint_jacobian_params(params, q, pose, Jq_twin);
    EXPECT_TRUE(jacobians_match(Jq_twin, Jq_hand, 1e-12, t.hand->parameters().names()));
  }
}

TEST(AutoDiff, SerialJointJacobianEqualsTheHandWrittenOne) {
  for (const auto& model : {make_puma560(), make_ur5()}) {
    const Twins t = twins_of(model, 14);
    const auto& hand = static_cast<const SerialArm&>(t.hand->mechanism());
    const auto& twin = static_cast<const testing::AutoDiffSerialArm&>(t.twin->mechanism());
    const VectorXd params = t.scenario.truth.head(hand.num_parameters());
    for (int j = 0; j < t.scenario.calibration.size(); ++j) {
      const VectorXd q = t.scenario.calibration.actuators.row(j).transpose();
      Matrix6Xd J_hand(6, hand.num_joints()), J_twin(6, hand.num_joints());
      const Pose a = hand.joint_jacobian(params, q, J_hand);
      const Pose b = twin.joint_jacobian(params, q, J_twin);
      EXPECT_LT(pose_difference(a, b).norm(), 1e-9);
      EXPECT_TRUE(jacobians_match(J_twin, J_hand, 1e-10, hand.actuator_names()));
    }
  }
}

TEST(AutoDiff, SensorJacobiansEqualTheHandWrittenOnesAndFiniteDifferences) {
  const LengthGauge hand("gauge", Vector3d(-200, 500, 500), Vector3d(-200, 205, -5), 0.3);
  const testing::AutoDiffLengthGauge twin(hand);
  const VectorXd params = (VectorXd(7) << -199, 501, 502, -201, 204, -6, 0.4).finished();
  for (int k = 0; k < 4; ++k) {
    Pose pose;
    pose.translation = Vector3d(3 * k, -2 * k, 410 + k);
    pose.rotation = exp_so3(Vector3d(0.1 * k, -0.05, 0.02 * k));
    VectorXd r_hand(1), r_twin(1), r_plain(1);
    MatrixXd Jp_hand(1, 6), Jp_twin(1, 6), Jq_hand(1, 7), Jq_twin(1, 7);
    hand.predict(params, pose, r_hand, &Jp_hand, &Jq_hand);
    twin.predict(params, pose, r_twin, &Jp_twin, &Jq_twin);
    twin.predict(params, pose, r_plain, nullptr, nullptr);
    EXPECT_NEAR(r_twin[0], r_hand[0], 1e-10);
    EXPECT_EQ(r_plain[0], r_twin[0]);
    EXPECT_TRUE(jacobians_match(Jp_twin, Jp_hand, 1e-12));
    EXPECT_TRUE(jacobians_match(Jq_twin, Jq_hand, 1e-12));
    auto at_params = [&](const VectorXd& p) {
      VectorXd r(1);
      twin.predict(p, pose, r, nullptr, nullptr);
      return r;
    };
    auto at_pose = [&](const VectorXd& delta) {
      VectorXd r(1);
      twin.predict(params, perturb(pose, delta), r, nullptr, nullptr);
      return r;
    };
    EXPECT_TRUE(jacobians_match(Jq_twin, numerical_jacobian(at_params, params, 1e-6), 1e-6));
    EXPECT_TRUE(
        jacobians_match(Jp_twin, numerical_jacobian(at_pose, VectorXd::Zero(6), 1e-6), 1e-6));
  }
}

TEST(AutoDiff, ResidualJacobianEqualsTheHandWrittenOneAndFiniteDifferences) {
  for (const auto& model : hand_models()) {
    const Twins t = twins_of(model, 15);
    SCOPED_TRACE(t.hand->mechanism().type());
    const auto hand_problem = t.scenario.make_problem();
    Scenario twin_scenario = t.scenario;
    twin_scenario.model = t.twin;
    const auto twin_problem = twin_scenario.make_problem();
    const VectorXd x = twin_problem->initial_free_parameters();
    VectorXd r_hand, r_twin;
    MatrixXd J_hand, J_twin;
    std::string why;
    ASSERT_TRUE(hand_problem->evaluate(x, &r_hand, &J_hand, &why)) << why;
    ASSERT_TRUE(twin_problem->evaluate(x, &r_twin, &J_twin, &why)) << why;
    EXPECT_LT((r_hand - r_twin).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_TRUE(jacobians_match(J_twin, J_hand, 1e-9, twin_problem->parameter_names()));
    auto residuals_at = [&](const VectorXd& p) {
      VectorXd out;
      EXPECT_TRUE(twin_problem->evaluate(p, &out, nullptr, &why)) << why;
      return out;
    };
    EXPECT_TRUE(jacobians_match(J_twin, numerical_jacobian(residuals_at, x, 1e-6), 1e-6,
                                twin_problem->parameter_names()));
  }
}

TEST(AutoDiff, LmOnTheTwinLandsWhereTheHandWrittenModelDoes) {
  if (!SolverRegistry::global().contains("lm")) GTEST_SKIP() << "lm is not built";
  ScenarioOptions options;
  options.num_configurations = 60;
  options.noise_half_width.set(kincal::kMillimetre, 0.0125);
  options.num_validation = 0;
  options.seed = 1;
  const Scenario hand = make_scenario(make_cube_hexapod(), options);
  Scenario twin = hand;
  twin.model = autodiff_twin(*make_cube_hexapod());
  const auto solver = SolverRegistry::global().create("lm");
  VectorXd x_hand = hand.make_problem()->initial_free_parameters();
  VectorXd x_twin = x_hand;
  const Summary a = solver->solve(*hand.make_problem(), x_hand, {});
  const Summary b = solver->solve(*twin.make_problem(), x_twin, {});
  ASSERT_TRUE(a.converged() && b.converged());
  // Case 5 is flat (parameters 4.8 mm RMS from the truth at the optimum): Jacobians equal to
  // rounding change the end game (12 or 16 iterations) and move the solution by ~1e-5 mm, as
  // any reordering of the arithmetic does; the minimum is the same.
  EXPECT_NEAR(a.final_cost, b.final_cost, 1e-9 * a.final_cost);
  EXPECT_LT((x_hand - x_twin).cwiseAbs().maxCoeff(), 1e-4);
}

}  // namespace
}  // namespace kincal
