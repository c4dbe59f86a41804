// The URDF arm: forward kinematics against an independent product of the URDF's transforms,
// its analytic Jacobians against finite differences (skewed, parallel and prismatic axes,
// every error block non-zero), inverse kinematics of forward kinematics, the model file
// round trip and its errors, and the error model's regularity where DH is singular.

#include "kincal/models/urdf_arm.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "jacobian_check.hpp"
#include "kincal/framework/analysis/identifiability.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/models/model_io.hpp"
#include "kincal/models/point_tracker.hpp"
#include "urdf_chain.hpp"

namespace kincal {
namespace {

using kincal::testing::frame6;
using kincal::testing::independent_fk;
using kincal::testing::jacobians_match;
using kincal::testing::joint;
using kincal::testing::numerical_jacobian;

Vector6d pose_difference(const Pose& from, const Pose& to) {
  Vector6d d;
  d << to.translation - from.translation, log_so3(to.rotation * from.rotation.transpose());
  return d;
}

// Skewed, parallel (j2, j3: both about y, the DH-singular case), continuous and prismatic
// joints; a tip behind fixed joints; non-zero base and tool.
UrdfArmGeometry test_geometry() {
  UrdfArmGeometry g;
  g.base_link = "base_link";
  g.tip_link = "tool0";
  g.base = frame6(10, -20, 30, 0.1, -0.2, 0.3);
  g.joints = {
      joint("j1", UrdfJointType::kRevolute, frame6(0, 0, 89, 0, 0, 0), Vector3d(0, 0, 1)),
      joint("j2", UrdfJointType::kRevolute, frame6(0, 136, 0, 0, 1.5707963, 0), Vector3d(0, 1, 0)),
      joint("j3", UrdfJointType::kContinuous, frame6(0, -120, 425, 0, 0, 0), Vector3d(0, 1, 0)),
      joint("j4", UrdfJointType::kPrismatic, frame6(0, 0, 392, 0.2, 0, 0),
            Vector3d(0.3, 0.4, 0.866).normalized()),
      joint("j5", UrdfJointType::kRevolute, frame6(0, 93, 0, 0, 0, 0), Vector3d(1, 2, -3)),
  };
  g.tip = frame6(0, 82, 0, -1.5707963, 0, 0);
  g.tool = frame6(1, 2, 31, 0.01, 0.02, -0.03);
  return g;
}

// Every parameter moved, so that no column is tested only at zero.
VectorXd moved_parameters(const UrdfArm& arm) {
  VectorXd p = urdf_arm_parameters(arm.nominal_geometry());
  for (int i = 0; i < p.size(); ++i)
    p[i] += (arm.parameters()[i].unit == "rad" ? 0.02 : 1.5) * std::sin(1.3 * i + 0.4);
  return p;
}

TEST(UrdfArm, ForwardKinematicsIsTheProductOfTheUrdfTransforms) {
  const UrdfArm arm(test_geometry());
  const VectorXd p = moved_parameters(arm);
  const UrdfArmGeometry g = arm.geometry_from(p);
  for (int trial = 0; trial < 5; ++trial) {
    VectorXd q(arm.num_joints());
    for (int i = 0; i < q.size(); ++i) q[i] = std::sin(0.7 * trial + 1.9 * i) * (i == 3 ? 40 : 1.2);
    const ForwardKinematicsResult fk = arm.forward_kinematics(p, q, Pose{});
    ASSERT_TRUE(fk.ok());
    const Eigen::Isometry3d T = independent_fk(g, q);
    EXPECT_LT((T.translation() - fk.pose.translation).norm(), 1e-9);
    EXPECT_LT((T.linear() - fk.pose.rotation).norm(), 1e-12);
  }
}

TEST(UrdfArm, JacobiansMatchFiniteDifferences) {
  const UrdfArm arm(test_geometry());
  const VectorXd p = moved_parameters(arm);
  std::vector<std::string> names;
  for (const auto& parameter : arm.parameters()) names.push_back(parameter.name);
  for (int trial = 0; trial < 4; ++trial) {
    VectorXd q(arm.num_joints());
    for (int i = 0; i < q.size(); ++i) q[i] = std::cos(1.1 * trial + 0.8 * i) * (i == 3 ? 30 : 1.0);
    const Pose pose = arm.forward_kinematics(p, q, Pose{}).pose;
    Matrix6Xd J_params(6, arm.num_parameters());
    arm.pose_jacobian_params(p, q, pose, J_params);
    const auto by_params = [&](const VectorXd& x) -> VectorXd {
      return pose_difference(pose, arm.forward_kinematics(x, q, Pose{}).pose);
    };
    EXPECT_TRUE(jacobians_match(J_params, numerical_jacobian(by_params, p, 1e-6), 1e-7, names))
        << "trial " << trial;
    Matrix6Xd J_q(6, arm.num_joints());
    const Pose same = arm.joint_jacobian(p, q, J_q);
    EXPECT_LT((same.translation - pose.translation).norm(), 1e-12);
    const auto by_joints = [&](const VectorXd& x) -> VectorXd {
      return pose_difference(pose, arm.forward_kinematics(p, x, Pose{}).pose);
    };
    EXPECT_TRUE(jacobians_match(J_q, numerical_jacobian(by_joints, q, 1e-6), 1e-7))
        << "trial " << trial;
  }
}

TEST(UrdfArm, InverseKinematicsReturnsToTheJointsOfForwardKinematics) {
  UrdfArmGeometry g = test_geometry();
  for (auto& j : g.joints) j.home = 0.3;
  const UrdfArm arm(g);
  const VectorXd p = moved_parameters(arm);
  VectorXd q(arm.num_joints());
  for (int i = 0; i < q.size(); ++i) q[i] = 0.3 + 0.2 * std::sin(1.0 + i);
  const Pose pose = arm.forward_kinematics(p, q, Pose{}).pose;
  VectorXd solved(arm.num_joints());
  const InverseKinematicsResult ik = arm.inverse_kinematics(p, pose, solved);
  ASSERT_TRUE(ik.ok()) << ik.describe();
  const Pose reached = arm.forward_kinematics(p, solved, Pose{}).pose;
  EXPECT_LT(pose_difference(pose, reached).head<3>().norm(), 1e-8);
  // Five joints cannot reach an arbitrary pose: a status with the reason, never NaN.
  Pose far = pose;
  far.translation += Vector3d(0, 0, 5000);
  const InverseKinematicsResult miss = arm.inverse_kinematics(p, far, solved);
  EXPECT_FALSE(miss.ok());
  EXPECT_FALSE(miss.reason.empty());
  EXPECT_TRUE(solved.allFinite());
}

// Inverse kinematics is the chain's shared solver (models/serial_chain.hpp) from any start: a
// six-joint arm reaches a pose in several configurations, and a start near one of them
// returns that one, the branch a user correcting a target wants.
TEST(UrdfArm, InverseKinematicsFromAStartReturnsTheSolutionNearIt) {
  const auto model = make_ur5_urdf();
  const auto& arm = dynamic_cast<const UrdfArm&>(model->mechanism());
  const VectorXd p = model->parameters().nominal_values();
  VectorXd q_true(6);
  q_true << 0.4, -1.1, 1.3, -1.6, -1.4, 0.7;
  const Pose pose = arm.forward_kinematics(p, q_true, Pose{}).pose;
  // Another configuration reaching the same pose, found from starts spread over the joints.
  VectorXd other(6), solved(6), start(6);
  bool found = false;
  for (int k = 0; k < 40 && !found; ++k) {
    for (int i = 0; i < 6; ++i) start[i] = 2.5 * std::sin(1.3 * k + 2.1 * i + 0.5);
    if (arm.inverse_kinematics_from(p, pose, start, other).ok() &&
        (other - q_true).cwiseAbs().maxCoeff() > 0.5)
      found = true;
  }
  ASSERT_TRUE(found) << "no second configuration reaches the pose";
  for (const VectorXd& target : {q_true, other}) {
    VectorXd near = target;
    for (int i = 0; i < 6; ++i) near[i] += 0.05 * std::cos(3.0 * i);
    const InverseKinematicsResult ik = arm.inverse_kinematics_from(p, pose, near, solved);
    ASSERT_TRUE(ik.ok()) << ik.describe();
    EXPECT_LT((solved - target).cwiseAbs().maxCoeff(), 1e-6) << solved.transpose();
  }
  // Non-finite input is a status, never NaN.
  start.setConstant(NAN);
  EXPECT_EQ(arm.inverse_kinematics_from(p, pose, start, solved).status,
            InverseKinematicsStatus::kNonFinite);
}

// Where two axes are parallel the DH parameters of the link between them jump; the origin
// errors stay regular: with the DH-singular pair j2, j3 the identification Jacobian of a
// point at many configurations keeps every column and has the rank the geometry allows.
TEST(UrdfArm, OriginErrorsStayRegularAcrossParallelAxes) {
  const UrdfArm arm(test_geometry());
  const VectorXd p0 = urdf_arm_parameters(arm.nominal_geometry());
  MatrixXd J(0, arm.num_parameters());
  for (int c = 0; c < 40; ++c) {
    VectorXd q(arm.num_joints());
    for (int i = 0; i < q.size(); ++i)
      q[i] = std::sin(0.37 * c * (i + 1) + i) * (i == 3 ? 50 : 1.4);
    Matrix6Xd Jp(6, arm.num_parameters());
    arm.pose_jacobian_params(p0, q, Pose{}, Jp);
    J.conservativeResize(J.rows() + 6, Eigen::NoChange);
    J.bottomRows(6) = Jp;
  }
  std::vector<std::string> names;
  for (const auto& parameter : arm.parameters()) names.push_back(parameter.name);
  const Identifiability a = analyze_identifiability(J, names);
  EXPECT_TRUE(a.unseen.empty());
  // Pose measurements identify 6 base + 6 tool + per revolute joint 4 and per prismatic 2
  // (+ the offsets, which the 6-DOF errors absorb): the rank of a minimal model (Everett's
  // count 4R + 2P + 6), whatever the axes' arrangement.
  EXPECT_EQ(a.numerical_rank, 4 * 4 + 2 * 1 + 6);
  const std::vector<int> keep = identifiable_subset(J);
  EXPECT_EQ(static_cast<int>(keep.size()), a.numerical_rank);
  const auto dependent = dependent_parameters(J, names, keep);
  EXPECT_EQ(static_cast<int>(dependent.size()), arm.num_parameters() - a.numerical_rank);
  for (const auto& d : dependent) EXPECT_FALSE(d.equivalent.empty()) << d.name;
}

// The preset's free set is chosen with urdf_arm_parameter_priority: the reflector's position
// is the tool's or the target's, never the last joint's frame slid along its axis (which would
// move the URDF's flange).
TEST(UrdfArm, PreferredParametersKeepTheLinkFramesInPlace) {
  const auto model = make_ur5_urdf();
  const ParameterSet& p = model->parameters();
  EXPECT_EQ(p.num_free(), 27);
  EXPECT_FALSE(p[p.index_of("wrist_3_joint.origin.z")].free);
  int point = 0;
  for (const char* name : {"tool.x", "tool.y", "tool.z", "tool.rx", "tool.ry", "tool.rz",
                           "tracker.target.x", "tracker.target.y", "tracker.target.z"})
    point += p[p.index_of(name)].free;
  EXPECT_EQ(point, 3);  // the point's three coordinates on the flange, in the tool or target
  const auto priority = urdf_arm_parameter_priority(*model);
  EXPECT_EQ(priority[static_cast<std::size_t>(p.index_of("base.x"))], 0);
  EXPECT_EQ(priority[static_cast<std::size_t>(p.index_of("elbow_joint.offset"))], 1);
  EXPECT_EQ(priority[static_cast<std::size_t>(p.index_of("elbow_joint.origin.rz"))], 2);
  EXPECT_EQ(priority[static_cast<std::size_t>(p.index_of("tracker.frame.rz"))], 0);
}

TEST(UrdfArm, ModelFileRoundTripsAndNamesBadInput) {
  UrdfArmGeometry g = test_geometry();
  g.urdf_text = "<robot name=\"r\"/>";
  g.urdf_file = "r.urdf";
  auto arm = std::make_shared<UrdfArm>(g);
  auto tracker = std::make_shared<PointTracker>("tracker", Vector6d::Zero(), Vector3d(0, 0, 31));
  MeasurementModel model(arm, {tracker});
  model.parameters().set_free("*", true);
  VectorXd values = model.parameters().nominal_values();
  values.head(arm->num_parameters()) = moved_parameters(*arm);
  const auto first = model_to_json(model, values);
  const auto read = model_from_json(first, "m.json");
  const auto second = model_to_json(*read, read->parameters().nominal_values());
  // Degrees in the file: the first write may round an angle by an ulp; from then on the
  // file is a fixed point, and every value read back is the one written.
  const auto again = model_from_json(second, "m.json");
  EXPECT_EQ(second.dump(), model_to_json(*again, again->parameters().nominal_values()).dump());
  EXPECT_LT((read->parameters().nominal_values() - values).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(read->mechanism().actuator_names(),
            (std::vector<std::string>{"j1", "j2", "j3", "j4", "j5"}));
  EXPECT_EQ(read->mechanism().actuators()[3].unit, "mm");

  auto bad = first;
  bad["mechanism"]["joints"][1]["type"] = "floating";
  try {
    model_from_json(bad, "m.json");
    ADD_FAILURE() << "a floating joint was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mechanism.joints[1].type"), std::string::npos)
        << e.what();
  }
  bad = first;
  bad["mechanism"]["joints"][0]["home"] = 1;  // a revolute joint's home is home_deg
  EXPECT_THROW(model_from_json(bad, "m.json"), std::invalid_argument);
  bad = first;
  bad["mechanism"]["joints"][2]["lower_deg"] = -10;  // continuous: no limits
  EXPECT_THROW(model_from_json(bad, "m.json"), std::invalid_argument);
  bad = first;
  bad["mechanism"]["joints"][0]["axis"] = {0, 0, 0};
  EXPECT_THROW(model_from_json(bad, "m.json"), std::invalid_argument);
}

}  // namespace
}  // namespace kincal
