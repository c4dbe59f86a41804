// A calibration from joint angles alone, end to end on exact data: the ur5-urdf arm put into
// two sockets 50 mm apart by inverse kinematics of a perturbed "true" arm; calibrating from
// the nominal arm and wrong socket positions, with the fixture-distance constraint, recovers
// the true link lengths and sockets.

#include <gtest/gtest.h>

#include <cmath>

#include "kincal/framework/base/random.hpp"
#include "kincal/framework/calibration/calibration_solve.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/fixture_distance.hpp"
#include "kincal/models/socket.hpp"
#include "kincal/models/urdf_arm.hpp"

namespace kincal {
namespace {

TEST(SocketCalibration, RecoversLinksAndSocketsFromJointAnglesAlone) {
  const auto arm_model = make_ur5_urdf();
  const auto& arm = static_cast<const UrdfArm&>(arm_model->mechanism());
  const VectorXd arm_nominal = arm_model->parameters().nominal_values().head(arm.num_parameters());
  VectorXd home(arm.num_joints());
  arm.home_actuators(arm_nominal, home);
  const Pose home_pose = arm.forward_kinematics(arm_nominal, home, arm.home_pose()).pose;
  const Vector3d p0 = home_pose.translation + Vector3d(0, -25, 0);
  const Vector3d p1 = home_pose.translation + Vector3d(0, 25, 0);

  // Starting values: the sockets a few mm off.
  auto model = std::make_shared<MeasurementModel>(
      arm_model->mechanism_ptr(),
      std::vector<std::shared_ptr<const Sensor>>{
          std::make_shared<Socket>("socket0", p0 + Vector3d(3, -2, 4)),
          std::make_shared<Socket>("socket1", p1 + Vector3d(-2, 1, 3))});
  model->add_constraint(std::make_shared<FixtureDistance>("socket0", "socket1", 50, 0.01));
  for (const char* pattern :
       {"socket*", "elbow_joint.origin.x", "wrist_1_joint.origin.x", "wrist_2_joint.offset"})
    model->parameters().set_free(pattern, true);

  // The truth: longer and shorter links, a turned wrist, the sockets where they are.
  VectorXd truth = model->parameters().nominal_values();
  const auto& parameters = model->parameters();
  truth[parameters.index_of("elbow_joint.origin.x")] += 0.8;
  truth[parameters.index_of("wrist_1_joint.origin.x")] -= 0.5;
  truth[parameters.index_of("wrist_2_joint.offset")] += 0.002;
  truth.segment<3>(parameters.index_of("socket0.point.x")) = p0;
  truth.segment<3>(parameters.index_of("socket1.point.x")) = p1;

  // 12 configurations per socket: the tool point in the socket, the flange turned about it.
  const int per_socket = 12;
  Measurements data;
  data.actuators.resize(2 * per_socket, arm.num_joints());
  data.readings.setConstant(2 * per_socket, model->num_readings(), NAN);
  Random rng(24);
  for (int c = 0; c < 2 * per_socket; ++c) {
    Pose target = home_pose;
    target.translation = c < per_socket ? p0 : p1;
    target.rotation =
        exp_so3(Vector3d(rng.symmetric(0.4), rng.symmetric(0.4), rng.symmetric(0.4))) *
        home_pose.rotation;
    VectorXd q(arm.num_joints());
    const auto ik = arm.inverse_kinematics(truth.head(arm.num_parameters()), target, q);
    ASSERT_TRUE(ik.ok()) << ik.describe();
    data.actuators.row(c) = q.transpose();
    data.readings.block(c, c < per_socket ? 0 : 3, 1, 3).setZero();
  }

  const CalibrationProblem problem(model, data, model->parameters().nominal_values(),
                                   model->parameters().free_indices());
  VectorXd x = problem.initial_free_parameters();
  const auto solver = SolverRegistry::global().create("lm");
  SolverOptions options;
  options.max_iterations = 100;
  const Summary summary =
      solve_calibration(*solver, problem, Prior{}, x, options, Formulation::kNested).summary;
  ASSERT_EQ(summary.termination, TerminationType::kConverged) << summary.message;
  const VectorXd estimate = problem.full_parameters(x);
  for (int i : problem.free_indices())
    EXPECT_NEAR(estimate[i], truth[i], 1e-5) << parameters[i].name;
  const Vector3d a = estimate.segment<3>(parameters.index_of("socket0.point.x"));
  const Vector3d b = estimate.segment<3>(parameters.index_of("socket1.point.x"));
  EXPECT_NEAR((a - b).norm(), 50, 1e-6);
}

}  // namespace
}  // namespace kincal
