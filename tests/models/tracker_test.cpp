// Point and pose trackers: known readings, Jacobians against finite differences (tangent
// space for the pose tracker's rotation), the SE(3) residual and its retraction, model files.

#include <gtest/gtest.h>

#include <cmath>

#include "jacobian_check.hpp"
#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/models/point_tracker.hpp"
#include "kincal/models/pose_tracker.hpp"
#include "sensor_values.hpp"

namespace kincal {
namespace {

using kincal::testing::frame_params;
using kincal::testing::jacobians_match;
using kincal::testing::numerical_jacobian;
using kincal::testing::params_of;

Pose random_pose(Random& rng, double position, double angle) {
  Vector6d delta;
  for (int i = 0; i < 6; ++i) delta[i] = rng.symmetric(i < 3 ? position : angle);
  return perturb(Pose{}, delta);
}

// The sensor's Jacobians against central differences of its reading error, the space its
// rows live in (plain differences for a point tracker).
void expect_jacobians_match_finite_differences(const Sensor& sensor, const VectorXd& params,
                                               const Pose& pose) {
  const int n = sensor.num_readings();
  VectorXd reading(n);
  MatrixXd J_pose(n, 6), J_params(n, sensor.num_parameters());
  sensor.predict(params, pose, reading, &J_pose, &J_params);
  auto error_from = [&](const VectorXd& other) {
    VectorXd e(n);
    sensor.reading_error(other, reading, e, nullptr);
    return e;
  };
  auto by_pose = [&](const VectorXd& delta) {
    VectorXd r(n);
    sensor.predict(params, perturb(pose, delta), r, nullptr, nullptr);
    return error_from(r);
  };
  auto by_params = [&](const VectorXd& p) {
    VectorXd r(n);
    sensor.predict(p, pose, r, nullptr, nullptr);
    return error_from(r);
  };
  std::vector<std::string> names;
  for (const auto& p : sensor.parameters()) names.push_back(p.name);
  // Step 1e-5: readings of about 2000 mm leave 1e-16 * 2000 / h of rounding in the quotient.
  EXPECT_TRUE(jacobians_match(J_pose, numerical_jacobian(by_pose, VectorXd::Zero(6), 1e-5), 1e-7))
      << sensor.name() << ": J_reading_pose";
  EXPECT_TRUE(jacobians_match(J_params, numerical_jacobian(by_params, params, 1e-5), 1e-7, names))
      << sensor.name() << ": J_reading_params";
}

TEST(PointTracker, ReadsTheTargetInTrackerCoordinates) {
  // Tracker at (1000, 0, 0) turned by 90 degrees about z: its x axis is the base's y axis.
  const PointTracker tracker("lt", frame_params(Vector3d(1000, 0, 0), Vector3d(0, 0, kPi / 2)),
                             Vector3d(10, 20, 30));
  Pose pose;
  pose.translation = Vector3d(500, 100, 200);
  VectorXd reading(3);
  tracker.predict(params_of(tracker), pose, reading, nullptr, nullptr);
  // Target in base coordinates (510, 120, 230); from the tracker (-490, 120, 230), which in
  // its axes (x = base y, y = -base x) is (120, 490, 230).
  EXPECT_LT((reading - Vector3d(120, 490, 230)).norm(), 1e-12);
  EXPECT_EQ(tracker.reading_names(), (std::vector<std::string>{"lt.x", "lt.y", "lt.z"}));
  EXPECT_EQ(tracker.parameters()[3].name, "lt.frame.rx");
  EXPECT_EQ(tracker.parameters()[8].name, "lt.target.z");
  EXPECT_FALSE(tracker.has_manifold_readings());
}

TEST(PointTracker, JacobiansMatchFiniteDifferences) {
  Random rng(41);
  for (int trial = 0; trial < 10; ++trial) {
    const PointTracker tracker("lt",
                               frame_params(Vector3d(2000, 500, 300), Vector3d(0.2, -0.3, 2.8)),
                               Vector3d(60, 40, 120));
    VectorXd params = params_of(tracker);
    for (int i = 0; i < params.size(); ++i) params[i] += rng.symmetric(i % 6 < 3 ? 5.0 : 0.1);
    expect_jacobians_match_finite_differences(tracker, params, random_pose(rng, 500, 2.0));
  }
}

TEST(PoseTracker, ReadsTheMarkersPositionAndRotationVector) {
  // Tracker at the base origin turned by 90 degrees about z; marker 100 mm along the end
  // effector's x, turned by 30 degrees about its z; the end effector at (0, 0, 500).
  const PoseTracker tracker("cam", frame_params(Vector3d::Zero(), Vector3d(0, 0, kPi / 2)),
                            frame_params(Vector3d(100, 0, 0), Vector3d(0, 0, kPi / 6)));
  Pose pose;
  pose.translation = Vector3d(0, 0, 500);
  VectorXd reading(6);
  tracker.predict(params_of(tracker), pose, reading, nullptr, nullptr);
  // Marker at (100, 0, 500) in the base: (0, -100, 500) in the tracker's axes; its rotation
  // Rz(-90) Rz(30) = Rz(-60 degrees).
  EXPECT_LT((reading.head<3>() - Vector3d(0, -100, 500)).norm(), 1e-12);
  EXPECT_LT((reading.tail<3>() - Vector3d(0, 0, -kPi / 3)).norm(), 1e-12);
  EXPECT_EQ(tracker.reading_units(),
            (std::vector<std::string>{"mm", "mm", "mm", "rad", "rad", "rad"}));
  EXPECT_EQ(tracker.reading_names()[5], "cam.rotvec_z");
  EXPECT_TRUE(tracker.has_manifold_readings());
}

TEST(PoseTracker, JacobiansMatchFiniteDifferencesInTheTangentSpace) {
  Random rng(42);
  for (int trial = 0; trial < 10; ++trial) {
    const PoseTracker tracker("cam",
                              frame_params(Vector3d(1500, -1200, 900), Vector3d(-1.7, 0.26, 2.1)),
                              frame_params(Vector3d(30, -40, 50), Vector3d(0.17, -0.35, 0.52)));
    VectorXd params = params_of(tracker);
    for (int i = 0; i < params.size(); ++i) params[i] += rng.symmetric(i % 6 < 3 ? 5.0 : 0.1);
    // Up to 3 rad: readings with rotation vectors near the flip at pi are covered too.
    expect_jacobians_match_finite_differences(tracker, params, random_pose(rng, 500, 3.0));
  }
}

TEST(PoseTracker, RetractIsTheInverseOfTheReadingError) {
  const PoseTracker tracker("cam", Vector6d::Zero(), Vector6d::Zero());
  Random rng(43);
  for (double size : {1e-9, 1e-3, 0.5, 1.7}) {  // |d| < pi: log's range
    for (int trial = 0; trial < 10; ++trial) {
      VectorXd measured(6), delta(6), moved, error(6);
      const Vector3d axis = Vector3d(rng.symmetric(1), rng.symmetric(1), rng.symmetric(1));
      measured << rng.symmetric(500), rng.symmetric(500), rng.symmetric(500),
          rng.symmetric(1.0) * 3.0 * axis.normalized();  // rotations up to 3 rad
      for (int i = 0; i < 6; ++i) delta[i] = rng.symmetric(i < 3 ? 10.0 : size);
      moved = measured;
      tracker.retract(moved, delta);
      tracker.reading_error(moved, measured, error, nullptr);
      EXPECT_LT((error - delta).norm(), 1e-12 * (1 + delta.norm())) << "size " << size;
      // The same reading gives no error, and swapping the two negates it (log(R^T) =
      // -log(R)).
      tracker.reading_error(measured, measured, error, nullptr);
      EXPECT_LT(error.norm(), 1e-15);
      VectorXd back(6);
      tracker.reading_error(measured, moved, back, nullptr);
      tracker.reading_error(moved, measured, error, nullptr);
      EXPECT_LT((back + error).norm(), 1e-12 * (1 + delta.norm()));
    }
  }
}

TEST(PoseTracker, ErrorJacobianIsTheInverseLeftJacobian) {
  // d/dd reading_error(retract(predicted, d), measured) at d = 0 is J_error_predicted.
  const PoseTracker tracker("cam", Vector6d::Zero(), Vector6d::Zero());
  Random rng(44);
  for (int trial = 0; trial < 10; ++trial) {
    VectorXd predicted(6), measured(6), error(6);
    for (int i = 0; i < 6; ++i) {
      predicted[i] = rng.symmetric(i < 3 ? 500.0 : 1.5);
      measured[i] = predicted[i] + rng.symmetric(i < 3 ? 5.0 : 0.5);
    }
    MatrixXd J(6, 6);
    tracker.reading_error(predicted, measured, error, &J);
    auto at = [&](const VectorXd& d) {
      VectorXd moved = predicted, e(6);
      tracker.retract(moved, d);
      tracker.reading_error(moved, measured, e, nullptr);
      return e;
    };
    EXPECT_TRUE(jacobians_match(J, numerical_jacobian(at, VectorXd::Zero(6), 1e-6), 1e-7));
  }
}

// --- model files ---

std::string sensor_read_error(const std::string& type, const Json& j) {
  try {
    ModelRegistry::global().sensor(type).read(j, JsonPath("m.json", "sensors[0]"));
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(TrackerFiles, RoundTripAndErrorsNameTheField) {
  const PointTracker point("lt", frame_params(Vector3d(2000, 600, 300), Vector3d(0.1, 0.2, 2.8)),
                           Vector3d(60, 40, 120));
  const PoseTracker pose("cam", frame_params(Vector3d(1500, -1200, 900), Vector3d(-1.7, 0.26, 2.1)),
                         frame_params(Vector3d(30, -40, 50), Vector3d(0.17, -0.35, 0.52)));
  for (const Sensor* sensor :
       {static_cast<const Sensor*>(&point), static_cast<const Sensor*>(&pose)}) {
    const SensorType& type = ModelRegistry::global().sensor(sensor->type());
    Json j = type.write(*sensor, params_of(*sensor));
    j["type"] = sensor->type();
    const auto back = type.read(j, JsonPath("m.json"));
    EXPECT_EQ(back->name(), sensor->name());
    EXPECT_LT((params_of(*back) - params_of(*sensor)).norm(), 1e-12) << sensor->type();
  }
  Json j = ModelRegistry::global().sensor("point-tracker").write(point, params_of(point));
  j["type"] = "point-tracker";
  Json bad = j;
  bad.erase("target");
  EXPECT_EQ(sensor_read_error("point-tracker", bad), "m.json: sensors[0]: missing key 'target'");
  bad = j;
  bad["target"] = {1, 2};
  EXPECT_EQ(sensor_read_error("point-tracker", bad)
                .rfind("m.json: sensors[0].target: expected an "
                       "array of 3 numbers",
                       0),
            0u);
  bad = j;
  bad["frame"]["rotation_zyx_deg"][1] = "x";
  EXPECT_EQ(sensor_read_error("point-tracker", bad)
                .rfind("m.json: sensors[0].frame.rotation_zyx_deg[1]: expected a number", 0),
            0u);
  bad = j;
  bad["marker"] = j["frame"];
  EXPECT_EQ(
      sensor_read_error("point-tracker", bad).rfind("m.json: sensors[0]: unknown key 'marker'", 0),
      0u);
  Json p = ModelRegistry::global().sensor("pose-tracker").write(pose, params_of(pose));
  p.erase("marker");
  EXPECT_EQ(sensor_read_error("pose-tracker", p), "m.json: sensors[0]: missing key 'marker'");
  p = ModelRegistry::global().sensor("pose-tracker").write(pose, params_of(pose));
  p["name"] = "my cam";
  EXPECT_EQ(sensor_read_error("pose-tracker", p)
                .rfind("m.json: sensors[0].name: expected a name within kincal's name policy, got "
                       "\"my cam\", which contains ' '",
                       0),
            0u);
}

}  // namespace
}  // namespace kincal
