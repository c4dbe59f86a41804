// The imported arm's discrete symmetries (UrdfArm::nearer_equivalent): a parameter vector
// whose joint zeros lie on the other branch is mapped to one nearer nominal with the same
// forward kinematics, checked against an independent product of the URDF's transforms; only
// changeable parameters move; and nothing is proposed when the map would need a fixed one.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/kinematics/units.hpp"
#include "kincal/models/urdf_arm.hpp"
#include "urdf_chain.hpp"

namespace kincal {
namespace {

using kincal::testing::frame6;
using kincal::testing::independent_fk;
using kincal::testing::joint;

// A UR-like chain (three parallel axes, where the solver's flips happen) with a skewed and a
// prismatic joint after it.
UrdfArmGeometry arm_geometry() {
  UrdfArmGeometry g;
  g.base_link = "base_link";
  g.tip_link = "tool0";
  g.joints = {
      joint("pan", UrdfJointType::kRevolute, frame6(0, 0, 89, 0, 0, 0), Vector3d(0, 0, 1)),
      joint("lift", UrdfJointType::kRevolute, frame6(0, 0, 0, kPi / 2, 0, 0), Vector3d(0, 0, 1)),
      joint("elbow", UrdfJointType::kRevolute, frame6(-425, 0, 0, 0, 0, 0), Vector3d(0, 0, 1)),
      joint("wrist1", UrdfJointType::kRevolute, frame6(-392, 0, 109, 0, 0, 0), Vector3d(0, 0, 1)),
      joint("wrist2", UrdfJointType::kRevolute, frame6(0, -94, 0, kPi / 2, 0, 0.3),
            Vector3d(0.2, 0.1, 1)),
      joint("slide", UrdfJointType::kPrismatic, frame6(0, 0, 82, -kPi / 2, 0, 0),
            Vector3d(0, 0, 1)),
  };
  g.tip = frame6(0, 0, 20, 0, 0, 0);
  g.tool = frame6(3, -2, 31, 0, 0, 0);
  return g;
}

double largest_pose_difference(const UrdfArm& arm, const VectorXd& a, const VectorXd& b) {
  double worst = 0;
  for (int k = 0; k < 40; ++k) {
    VectorXd q(arm.num_joints());
    for (int i = 0; i < q.size(); ++i) q[i] = 2.5 * std::sin(0.7 * k + 1.9 * i + 0.3);
    const Eigen::Isometry3d ta = independent_fk(arm.geometry_from(a), q);
    const Eigen::Isometry3d tb = independent_fk(arm.geometry_from(b), q);
    worst = std::max(worst, (ta.translation() - tb.translation()).norm());
    worst = std::max(worst, 1000 * (ta.linear() - tb.linear()).norm());
  }
  return worst;
}

struct Fixture {
  UrdfArm arm{arm_geometry()};
  VectorXd nominal = urdf_arm_parameters(arm.nominal_geometry());
  VectorXd scale = VectorXd::Constant(nominal.size(), 1.0);
  Fixture() {
    for (int i = 0; i < scale.size(); ++i)
      scale[i] = arm.parameters()[i].unit == kRadian ? 0.01 : 5;
  }
  // Small errors everywhere: a calibrated arm near nominal.
  VectorXd near_nominal() const {
    VectorXd p = nominal;
    for (int i = 0; i < p.size(); ++i)
      p[i] += (arm.parameters()[i].unit == kRadian ? 0.003 : 0.4) * std::sin(2.1 * i + 0.5);
    return p;
  }
  int offset_of(int joint) const { return UrdfArm::joint_index(joint) + UrdfArm::kOffset; }
};

// The arm `p` with joint `turned`'s zero turned by pi and the next joint's origin turned back
// (E' = C^-1 R(pi) C E, the rotation about the turned joint's axis): one of the equivalent
// parameter vectors a solver can end at, built here by hand; the test checks that it is one.
VectorXd twin_of(const UrdfArm& arm, const VectorXd& p, int turned) {
  VectorXd twin = p;
  twin[UrdfArm::joint_index(turned) + UrdfArm::kOffset] += kPi;
  const UrdfArmGeometry g = arm.nominal_geometry();
  const auto iso = [](const Vector6d& f) {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.translation() = f.head<3>();
    t.linear() = rotation_from_euler_zyx(Vector3d(f[5], f[4], f[3]));
    return t;
  };
  const int next = turned + 1;
  Eigen::Isometry3d turn = Eigen::Isometry3d::Identity();
  turn.linear() = Eigen::AngleAxisd(kPi, g.joints[turned].axis).toRotationMatrix();
  const Eigen::Isometry3d C = iso(g.joints[next].origin);
  const Eigen::Isometry3d E = iso(p.segment<6>(UrdfArm::joint_index(next)));
  const Eigen::Isometry3d moved = C.inverse() * turn * C * E;
  Pose pose;
  pose.rotation = moved.linear();
  pose.translation = moved.translation();
  twin.segment<6>(UrdfArm::joint_index(next)) = frame_parameters(pose);
  return twin;
}

TEST(UrdfArmSymmetry, AZeroOnTheOtherBranchIsMappedBackWithTheSamePoses) {
  Fixture f;
  const std::vector<bool> all(static_cast<std::size_t>(f.nominal.size()), true);
  for (int turned : {1, 2, 4}) {
    const VectorXd truth = f.near_nominal();
    const VectorXd twin = twin_of(f.arm, truth, turned);
    ASSERT_LT(largest_pose_difference(f.arm, truth, twin), 1e-9) << "the test's twin";

    VectorXd back;
    std::string what;
    ASSERT_TRUE(f.arm.nearer_equivalent(twin, f.nominal, all, f.scale, back, &what)) << turned;
    EXPECT_LT(largest_pose_difference(f.arm, twin, back), 1e-9) << what;
    EXPECT_LT(std::abs(wrap_angle(back[f.offset_of(turned)] - f.nominal[f.offset_of(turned)])), 0.1)
        << what;
    // Every parameter back where it was (angles up to whole turns).
    for (int i = 0; i < back.size(); ++i) {
      const double d = f.arm.parameters()[i].unit == kRadian ? wrap_angle(back[i] - truth[i])
                                                             : back[i] - truth[i];
      EXPECT_NEAR(d, 0, 1e-7) << f.arm.parameters()[i].name << " after " << what;
    }
    EXPECT_NE(what.find(f.arm.parameters()[f.offset_of(turned)].name), std::string::npos) << what;
  }
}

TEST(UrdfArmSymmetry, OnlyChangeableParametersMoveAndNothingIsProposedWithoutThem) {
  Fixture f;
  std::vector<bool> all(static_cast<std::size_t>(f.nominal.size()), true);
  const VectorXd truth = f.near_nominal();
  const VectorXd twin = twin_of(f.arm, truth, 1);
  // With lift's own origin error and every one after it fixed, and the tool, no map can
  // undo the turn: nothing is proposed.
  std::vector<bool> none_after = all;
  for (int j = 1; j < f.arm.num_joints(); ++j)
    for (int k = 0; k < 6; ++k)
      none_after[static_cast<std::size_t>(UrdfArm::joint_index(j) + k)] = false;
  for (int k = 0; k < 6; ++k) none_after[static_cast<std::size_t>(f.arm.tool_index() + k)] = false;
  VectorXd back;
  EXPECT_FALSE(f.arm.nearer_equivalent(twin, f.nominal, none_after, f.scale, back, nullptr));
  // With lift's own origin free, the turn goes back there; only changeable parameters move.
  std::vector<bool> own = none_after;
  for (int k = 0; k < 6; ++k) own[static_cast<std::size_t>(UrdfArm::joint_index(1) + k)] = true;
  std::string what;
  ASSERT_TRUE(f.arm.nearer_equivalent(twin, f.nominal, own, f.scale, back, &what));
  for (int i = 0; i < back.size(); ++i) {
    if (!own[static_cast<std::size_t>(i)]) {
      EXPECT_EQ(back[i], twin[i]) << i;
    }
  }
  EXPECT_LT(largest_pose_difference(f.arm, twin, back), 1e-9) << what;
  EXPECT_LT(std::abs(wrap_angle(back[f.offset_of(1)] - f.nominal[f.offset_of(1)])), 0.1) << what;
  // A vector already nearest nominal: nothing to map.
  EXPECT_FALSE(f.arm.nearer_equivalent(truth, f.nominal, all, f.scale, back, nullptr));
}

}  // namespace
}  // namespace kincal
