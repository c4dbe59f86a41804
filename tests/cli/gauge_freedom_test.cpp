// Issue 35, item A7: a calibration from joint angles alone (a tool point put into sockets whose
// positions are unknown, a known distance between two of them) cannot see where the whole
// setup stands: moving the arm's base and every socket together by a rigid motion changes no
// fit. A shift of the setup is an exact null direction of the Jacobian; a turn is not, since
// it turns every residual t - p, which the Jacobian sees wherever the tool misses its socket.
// The automatic choice of an imported arm's parameters kept those three turns as if the data
// determined them, with standard deviations that describe nothing (0.03-0.08 rad on the Panda
// socket data, the sockets' positions 10-50 mm). Here on a simulated socket calibration of
// ur5-urdf's arm: the check keeps exactly what the data determine, the base frame holds the
// measurement frame, and every standard deviation then describes the estimate's real error.

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

#include "kincal/framework/analysis/identifiability_check.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/calibration/constrained_problem.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/framework/least_squares/uncertainty.hpp"
#include "kincal/models/fixture_distance.hpp"
#include "kincal/models/socket.hpp"
#include "kincal/models/urdf_arm.hpp"

namespace kincal::cli {
namespace {

constexpr int kSockets = 3, kPerSocket = 16;
constexpr double kJointNoise = 2e-5;  // rad: the encoders' noise; the readings are exactly 0

bool is_socket_parameter(const std::string& name) {
  return name.size() > 3 && name[0] == 's' && std::isdigit(static_cast<unsigned char>(name[1])) &&
         name[2] == '.';
}

struct SocketCalibration {
  std::shared_ptr<MeasurementModel> model;
  VectorXd truth, start;
  std::vector<Vector3d> sockets;  ///< the true centres, in the arm's base coordinates
  Measurements data;
};

// ur5-urdf's arm with its tool point 40, 25, 60 mm off the flange's centre (off joint 6's
// axis), three sockets and 50 mm between sockets 0 and 1; every parameter free, as `kincal
// model --urdf` writes an imported arm. The truth errs in every joint from the second on and
// in the tool (the base and the first joint, which the data cannot see, are the nominal
// ones).
SocketCalibration simulate_socket_calibration() {
  SocketCalibration s;
  const auto arm_model = make_ur5_urdf();
  const Mechanism& arm = arm_model->mechanism();
  const int n_arm = arm.num_parameters();
  VectorXd arm_truth = arm_model->parameters().nominal_values().head(n_arm);
  const std::vector<std::string> names = arm_model->parameters().names();
  Random rng(35);
  for (int i = 0; i < n_arm; ++i) {
    const std::string& name = names[static_cast<std::size_t>(i)];
    if (name.rfind("base.", 0) == 0 || name.rfind("shoulder_pan_joint.", 0) == 0) continue;
    const bool angle = arm_model->parameters()[i].unit == "rad";
    arm_truth[i] += rng.symmetric(angle ? 2e-3 : 1.0);
  }
  const Vector3d tool_point(40, 25, 60);
  for (int a = 0; a < 3; ++a)
    arm_truth[arm_model->parameters().index_of(std::string("tool.") + "xyz"[a])] += tool_point[a];

  // The sockets where the true arm's tool point is at three configurations around home, and
  // in each the tool put in at 16 orientations (inverse kinematics of the true arm), the
  // joint angles then recorded with noise.
  VectorXd home(arm.num_actuators()), q(arm.num_actuators());
  EXPECT_TRUE(arm.home_actuators(arm_truth, home).ok());
  std::vector<VectorXd> configurations;
  std::vector<int> socket_of;
  for (int k = 0; k < kSockets; ++k) {
    VectorXd centre = home;
    for (int i = 0; i < centre.size(); ++i) centre[i] += 0.5 * std::sin(1.7 * k + 0.9 * i + 0.4);
    s.sockets.push_back(
        arm.forward_kinematics(arm_truth, centre, arm.home_pose()).pose.translation);
    int taken = 0;
    for (int c = 0; taken < kPerSocket && c < 4 * kPerSocket; ++c) {
      VectorXd near = centre;
      for (int i = 0; i < near.size(); ++i) near[i] += rng.symmetric(0.35);
      Pose pose = arm.forward_kinematics(arm_truth, near, arm.home_pose()).pose;
      pose.translation = s.sockets.back();
      if (!arm.inverse_kinematics(arm_truth, pose, q).ok()) continue;
      const Pose reached = arm.forward_kinematics(arm_truth, q, arm.home_pose()).pose;
      if ((reached.translation - s.sockets.back()).norm() > 1e-6) continue;
      for (int i = 0; i < q.size(); ++i)
        q[i] += rng.symmetric(kJointNoise * std::sqrt(3.0));  // uniform, std kJointNoise
      configurations.push_back(q);
      socket_of.push_back(k);
      ++taken;
    }
    EXPECT_EQ(taken, kPerSocket) << "socket " << k << ": inverse kinematics failed too often";
  }

  // The model: sockets starting a few millimetres from their centres.
  std::vector<std::shared_ptr<const Sensor>> sensors;
  for (int k = 0; k < kSockets; ++k)
    sensors.push_back(std::make_shared<Socket>("s" + std::to_string(k), s.sockets[k]));
  s.model = std::make_shared<MeasurementModel>(arm_model->mechanism_ptr(), sensors);
  s.model->add_constraint(
      std::make_shared<FixtureDistance>("s0", "s1", (s.sockets[0] - s.sockets[1]).norm(), 0.05));
  s.model->set_reading_std("s*", 0.1);
  s.model->parameters().set_free("*", true);
  s.truth = s.start = s.model->parameters().nominal_values();
  s.truth.head(n_arm) = arm_truth;
  for (int a = 0; a < 3; ++a)  // the tool point's nominal value is known to a few millimetres
    s.start[s.model->parameters().index_of(std::string("tool.") + "xyz"[a])] = tool_point[a] + 2;
  for (int k = 0; k < kSockets; ++k)
    for (int a = 0; a < 3; ++a)
      s.start[s.model->parameters().index_of("s" + std::to_string(k) + ".point." + "xyz"[a])] +=
          3.0 + a - k;
  const int readings = s.model->num_readings();
  const int m = static_cast<int>(configurations.size());
  s.data.actuators.resize(m, arm.num_actuators());
  s.data.readings.setConstant(m, readings, NAN);
  for (int c = 0; c < m; ++c) {
    s.data.actuators.row(c) = configurations[static_cast<std::size_t>(c)].transpose();
    s.data.readings.block(c, 3 * socket_of[static_cast<std::size_t>(c)], 1, 3).setZero();
  }
  return s;
}

TEST(GaugeFreedom, SocketsAloneKeepWhatTheDataDetermineAndTheBaseHoldsTheFrame) {
  const SocketCalibration s = simulate_socket_calibration();
  ASSERT_EQ(s.data.size(), kSockets * kPerSocket);
  const CalibrationProblem probe(s.model, s.data, s.start, s.model->parameters().free_indices());
  MatrixXd J;
  ASSERT_TRUE(probe.evaluate(probe.initial_free_parameters(), nullptr, &J));
  append_constraint_rows(probe, probe.initial_free_parameters(), J);
  const IdentifiabilityCheck check = check_identifiability(
      "sockets.csv", probe, J, WhenRankDeficient::kFixDependent, IdentifiabilityOptions{}, "");
  // A 6R arm measured at a point off its last axis determines 4 x 6 + 6 - 3 = 27 parameters
  // (the tracker page of docs/calibrating-a-serial-arm.md), 6 of them where the arm stands in
  // the measurement frame: with sockets, no instrument has a frame, so 21, and each socket's
  // centre: 21 + 3 x 3.
  EXPECT_EQ(check.free.size(), 21u + 3u * kSockets);
  // The measurement frame is held by the arm's base, all six of its parameters fixed; every
  // socket's centre is estimated (in the base's coordinates).
  for (const std::string axis : {"x", "y", "z", "rx", "ry", "rz"})
    EXPECT_EQ(std::count(check.fixed.begin(), check.fixed.end(), "base." + axis), 1)
        << "base." << axis << " is kept";
  for (const auto& name : check.fixed)
    EXPECT_FALSE(is_socket_parameter(name)) << name << " is fixed";

  // Calibrated on the kept parameters, every standard deviation is small: the sockets'
  // positions in the base's coordinates a fraction of a millimetre (before, through the
  // turns, tens of millimetres). And they describe the estimate: the distances between the
  // sockets, which no choice of coordinates changes, come out within five of their standard
  // deviations (propagated from the covariance) of the true ones.
  const CalibrationProblem problem(s.model, s.data, s.start, check.free);
  VectorXd x = problem.initial_free_parameters();
  SolverOptions options;
  const Summary summary = solve_nested_calibration(*SolverRegistry::global().create("lm"), problem,
                                                   Prior{}, x, options);
  ASSERT_TRUE(summary.converged()) << summary.message;
  VectorXd r;
  MatrixXd Jx;
  ASSERT_TRUE(problem.evaluate(x, &r, &Jx));
  append_constraint_rows(problem, x, Jx, &r);
  const ParameterUncertainty u = estimate_uncertainty(Jx, r);
  const std::vector<std::string> names = problem.parameter_names();
  for (std::size_t i = 0; i < names.size(); ++i) {
    const bool angle = s.model->parameters()[check.free[i]].unit == "rad";
    EXPECT_LT(u.std[static_cast<int>(i)],
              angle ? 1e-3 : (is_socket_parameter(names[i]) ? 0.1 : 0.5))
        << names[i];
  }
  const VectorXd estimate = problem.full_parameters(x);
  auto socket_index = [&](int k) {  // of s<k>.point.x among the free parameters
    const auto it = std::find(names.begin(), names.end(), "s" + std::to_string(k) + ".point.x");
    return static_cast<int>(it - names.begin());
  };
  for (int a = 0; a < kSockets; ++a)
    for (int b = a + 1; b < kSockets; ++b) {
      const int ia = socket_index(a), ib = socket_index(b);
      ASSERT_LT(std::max(ia, ib) + 2, static_cast<int>(names.size()));
      const Vector3d pa = estimate.segment<3>(check.free[static_cast<std::size_t>(ia)]);
      const Vector3d pb = estimate.segment<3>(check.free[static_cast<std::size_t>(ib)]);
      const Vector3d along = (pa - pb).normalized();
      VectorXd gradient = VectorXd::Zero(static_cast<int>(names.size()));
      gradient.segment<3>(ia) = along;
      gradient.segment<3>(ib) = -along;
      const double std = std::sqrt(gradient.dot(u.covariance * gradient));
      const double truth =
          (s.sockets[static_cast<std::size_t>(a)] - s.sockets[static_cast<std::size_t>(b)]).norm();
      EXPECT_NEAR((pa - pb).norm(), truth, 5 * std) << "s" << a << "-s" << b << ", std " << std;
    }
}

}  // namespace
}  // namespace kincal::cli
