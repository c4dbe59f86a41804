// The closed-form hand-eye solution (framework/kinematics/hand_eye.hpp): exact motions give X
// back; motions that cannot determine X are a reason, not a wrong X.

#include <gtest/gtest.h>

#include <random>

#include "kincal/framework/kinematics/hand_eye.hpp"

namespace kincal {
namespace {

Pose random_pose(std::mt19937& random, double angle, double distance) {
  std::normal_distribution<double> normal;
  Vector3d axis(normal(random), normal(random), normal(random));
  Pose p;
  p.rotation = exp_so3(axis.normalized() * angle * (0.5 + 0.5 * std::abs(normal(random))));
  p.translation = Vector3d(normal(random), normal(random), normal(random)) * distance;
  return p;
}

TEST(HandEye, RecoversTheMountFromExactMotions) {
  std::mt19937 random(7);
  const Pose X = random_pose(random, 1.2, 100);
  std::vector<Pose> A, B;
  for (int k = 0; k < 8; ++k) {
    const Pose a = random_pose(random, 0.6, 200);
    A.push_back(a);
    B.push_back(compose(inverse(X), compose(a, X)));  // A X = X B
  }
  const HandEyeSolution s = solve_hand_eye(A, B);
  ASSERT_TRUE(s.ok) << s.reason;
  EXPECT_LT((s.X.rotation - X.rotation).norm(), 1e-10);
  EXPECT_LT((s.X.translation - X.translation).norm(), 1e-8);
  EXPECT_LT(s.rotation_rms, 1e-10);
  EXPECT_LT(s.translation_rms, 1e-8);
  EXPECT_EQ(s.motions_used, 8);
}

TEST(HandEye, NoisyMotionsGiveANearbyMountAndSayHowWellTheyAgree) {
  std::mt19937 random(11);
  const Pose X = random_pose(random, 0.8, 50);
  std::vector<Pose> A, B;
  for (int k = 0; k < 20; ++k) {
    const Pose a = random_pose(random, 0.7, 150);
    A.push_back(a);
    Pose b = compose(inverse(X), compose(a, X));
    Vector6d noise;
    std::normal_distribution<double> normal;
    for (int i = 0; i < 6; ++i) noise[i] = normal(random) * (i < 3 ? 0.05 : 1e-4);
    B.push_back(perturb(b, noise));
  }
  const HandEyeSolution s = solve_hand_eye(A, B);
  ASSERT_TRUE(s.ok) << s.reason;
  EXPECT_LT(log_so3(s.X.rotation.transpose() * X.rotation).norm(), 1e-3);
  EXPECT_LT((s.X.translation - X.translation).norm(), 1.0);
  EXPECT_GT(s.rotation_rms, 1e-6);
}

TEST(HandEye, MotionsAboutParallelAxesAreRefusedWithTheReason) {
  std::mt19937 random(3);
  const Pose X = random_pose(random, 1.0, 100);
  std::vector<Pose> A, B;
  for (int k = 1; k <= 5; ++k) {
    Pose a;
    a.rotation = exp_so3(Vector3d(0, 0, 0.3 * k));  // every motion about z
    a.translation = Vector3d(10 * k, -5 * k, 0);
    A.push_back(a);
    B.push_back(compose(inverse(X), compose(a, X)));
  }
  const HandEyeSolution s = solve_hand_eye(A, B);
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.reason.find("parallel"), std::string::npos) << s.reason;
}

TEST(HandEye, TooFewTurningMotionsAreRefused) {
  std::vector<Pose> A(3), B(3);  // identity motions: nothing turns
  const HandEyeSolution s = solve_hand_eye(A, B);
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.reason.find("fewer than two"), std::string::npos) << s.reason;
}

}  // namespace
}  // namespace kincal
