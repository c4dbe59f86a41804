// The camera sensor: projection of known points by hand, its Jacobians against finite
// differences for both mountings with distortion, which points a simulated view sees, the
// target forms, model files (round trip and one-line refusals), and a simulated calibration
// of the camera, both mounts and the arm from pixels.

#include <gtest/gtest.h>

#include <cmath>

#include "jacobian_check.hpp"
#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/models/camera.hpp"
#include "kincal/models/model_io.hpp"
#include "kincal/models/presets.hpp"
#include "sensor_values.hpp"

namespace kincal {
namespace {

using kincal::testing::frame_params;
using kincal::testing::jacobians_match;
using kincal::testing::numerical_jacobian;
using kincal::testing::params_of;

CameraIntrinsics distorted() {
  CameraIntrinsics in;
  in.fx = 1210;
  in.fy = 1190;
  in.cx = 650;
  in.cy = 500;
  in.k1 = -0.12;
  in.k2 = 0.08;
  in.k3 = -0.03;
  in.p1 = 0.002;
  in.p2 = -0.0015;
  return in;
}

TEST(Camera, ProjectsAPointAsThePinholeAndOpenCvDistortionSay) {
  // Camera at the origin looking along base z; the target's frame at (0, 0, 1000) unturned;
  // one target point at (100, -50, 0): in the camera's frame (100, -50, 1000), so a = 0.1,
  // b = -0.05, r2 = 0.0125.
  CameraIntrinsics in = distorted();
  const Camera camera("cam", CameraMounting::kEyeInHand,
                      CameraTarget::from_points({Vector3d(100, -50, 0), Vector3d(0, 0, 0),
                                                 Vector3d(1, 0, 0), Vector3d(0, 1, 0)}),
                      Vector6d::Zero(), frame_params(Vector3d(0, 0, 1000), Vector3d::Zero()), in,
                      1280, 1024);
  VectorXd reading(camera.num_readings());
  camera.predict(params_of(camera), Pose{}, reading, nullptr, nullptr);
  const double a = 0.1, b = -0.05, r2 = a * a + b * b;
  const double radial = 1 + in.k1 * r2 + in.k2 * r2 * r2 + in.k3 * r2 * r2 * r2;
  const double ad = a * radial + 2 * in.p1 * a * b + in.p2 * (r2 + 2 * a * a);
  const double bd = b * radial + in.p1 * (r2 + 2 * b * b) + 2 * in.p2 * a * b;
  EXPECT_NEAR(reading[0], in.fx * ad + in.cx, 1e-9);
  EXPECT_NEAR(reading[1], in.fy * bd + in.cy, 1e-9);
  // The target's origin is on the optical axis: the principal point.
  EXPECT_NEAR(reading[2], in.cx, 1e-9);
  EXPECT_NEAR(reading[3], in.cy, 1e-9);
  EXPECT_EQ(camera.reading_names()[0], "cam.p0.u");
  EXPECT_EQ(camera.reading_names()[7], "cam.p3.v");
  EXPECT_EQ(camera.reading_units()[5], "px");
  EXPECT_EQ(camera.parameters()[Camera::kIntrinsicsIndex + 4].name, "cam.k1");
  EXPECT_EQ(camera.parameters()[Camera::kIntrinsicsIndex + 4].unit, "one");
}

TEST(Camera, EyeToHandSeesTheTargetMoveWithTheEndEffector) {
  // Camera 1000 mm above the base origin looking down (turned pi about x: its z is -z);
  // the target on the end effector; the end effector at (0, 0, 0): the target's origin is
  // on the optical axis; moving the end effector by +x moves it to the image's right.
  const Camera camera("cam", CameraMounting::kEyeToHand, CameraTarget::grid(2, 2, 10),
                      frame_params(Vector3d(0, 0, 1000), Vector3d(kPi, 0, 0)), Vector6d::Zero(),
                      CameraIntrinsics{}, 1280, 1024);
  VectorXd at_origin(8), moved(8);
  Pose pose;
  camera.predict(params_of(camera), pose, at_origin, nullptr, nullptr);
  EXPECT_NEAR(at_origin[0], 640, 1e-9);
  EXPECT_NEAR(at_origin[1], 512, 1e-9);
  pose.translation.x() = 100;
  camera.predict(params_of(camera), pose, moved, nullptr, nullptr);
  EXPECT_NEAR(moved[0], 640 + 1000 * 100 / 1000.0, 1e-9);
}

void expect_jacobians_match(const Camera& camera, const VectorXd& params, const Pose& pose) {
  const int n = camera.num_readings();
  VectorXd reading(n);
  MatrixXd J_pose(n, 6), J_params(n, camera.num_parameters());
  camera.predict(params, pose, reading, &J_pose, &J_params);
  auto by_pose = [&](const VectorXd& delta) {
    VectorXd r(n);
    camera.predict(params, perturb(pose, delta), r, nullptr, nullptr);
    return r;
  };
  auto by_params = [&](const VectorXd& p) {
    VectorXd r(n);
    camera.predict(p, pose, r, nullptr, nullptr);
    return r;
  };
  std::vector<std::string> names;
  for (const auto& p : camera.parameters()) names.push_back(p.name);
  EXPECT_TRUE(jacobians_match(J_pose, numerical_jacobian(by_pose, VectorXd::Zero(6), 1e-5), 1e-6))
      << mounting_name(camera.mounting()) << ": J_reading_pose";
  EXPECT_TRUE(jacobians_match(J_params, numerical_jacobian(by_params, params, 1e-6), 1e-6, names))
      << mounting_name(camera.mounting()) << ": J_reading_params";
}

TEST(Camera, JacobiansMatchFiniteDifferencesForBothMountingsWithDistortion) {
  Random rng(7);
  // A target that is not planar, turned frames, and distortion in every coefficient.
  const CameraTarget target =
      CameraTarget::from_points({Vector3d(0, 0, 0), Vector3d(40, 0, 5), Vector3d(0, 30, -4),
                                 Vector3d(40, 30, 2), Vector3d(20, 15, 10)});
  for (int trial = 0; trial < 4; ++trial) {
    Pose pose;
    pose.rotation = rotation_from_euler_zyx(
        Vector3d(rng.symmetric(0.3), rng.symmetric(0.3), rng.symmetric(0.3)));
    pose.translation = Vector3d(rng.symmetric(50), rng.symmetric(50), rng.symmetric(50));
    // Eye-to-hand: the camera 900 mm above, looking down at the end effector's target.
    const Camera fixed("cam", CameraMounting::kEyeToHand, target,
                       frame_params(Vector3d(10, -20, 900), Vector3d(kPi + 0.1, 0.05, 0.2)),
                       frame_params(Vector3d(-20, -15, 30), Vector3d(0.1, -0.2, 0.3)), distorted(),
                       1280, 1024);
    expect_jacobians_match(fixed, params_of(fixed), pose);
    // Eye-in-hand: the camera on the end effector looking along its z at a target 800 mm on.
    const Camera carried("cam", CameraMounting::kEyeInHand, target,
                         frame_params(Vector3d(5, 60, 30), Vector3d(0.05, -0.1, 0.3)),
                         frame_params(Vector3d(-20, -15, 800), Vector3d(0.2, 0.1, -0.3)),
                         distorted(), 1280, 1024);
    expect_jacobians_match(carried, params_of(carried), pose);
  }
}

TEST(Camera, ASimulatedViewMissesPointsOutsideTheImageAndBehindTheCamera) {
  // The 3 x 3 points of a grid 150 mm apart, 1000 mm in front of an eye-in-hand camera of
  // 300 x 300 px, centred on its axis: the outer points are 180 px off the axis, outside the
  // image. Given as points, the target loses those; as a grid (a chessboard), it is not
  // detected at all.
  CameraIntrinsics in;
  in.fx = in.fy = 1200;
  in.cx = in.cy = 149.5;
  const CameraTarget grid = CameraTarget::grid(3, 3, 150);
  const Vector6d board = frame_params(Vector3d(-150, -150, 1000), Vector3d::Zero());
  const Camera camera("cam", CameraMounting::kEyeInHand, CameraTarget::from_points(grid.points),
                      Vector6d::Zero(), board, in, 300, 300);
  const VectorXd params = params_of(camera);
  VectorXd reading(camera.num_readings());
  camera.predict(params, Pose{}, reading, nullptr, nullptr);
  EXPECT_EQ(camera.drop_unseen(params, Pose{}, reading), 16);  // only the centre (p4) is in
  for (int i = 0; i < 9; ++i) EXPECT_EQ(std::isnan(reading[2 * i]), i != 4) << "point " << i;
  const Camera chessboard("cam", CameraMounting::kEyeInHand, grid, Vector6d::Zero(), board, in, 300,
                          300);
  camera.predict(params, Pose{}, reading, nullptr, nullptr);
  EXPECT_EQ(chessboard.drop_unseen(params, Pose{}, reading), 18);
  // Seen edge-on (turned 80 degrees about the camera's y axis) the board is not detected.
  const Camera tilted("cam", CameraMounting::kEyeInHand, CameraTarget::grid(3, 3, 10),
                      Vector6d::Zero(), frame_params(Vector3d(0, 0, 1000), Vector3d(0, 1.4, 0)), in,
                      300, 300);
  for (const bool seen : tilted.visible_points(params_of(tilted), Pose{}, Camera::kMaxViewTilt))
    EXPECT_FALSE(seen);
  // Behind the camera: the camera does not read at all.
  Pose turned;
  turned.rotation = rotation_from_euler_zyx(Vector3d(0, kPi, 0));
  std::string why;
  EXPECT_FALSE(camera.reads_at(params, turned, &why));
  EXPECT_EQ(why, "target behind the camera");
  EXPECT_TRUE(camera.reads_at(params, Pose{}, nullptr));
}

TEST(CameraTarget, AGridIsNumberedRowByRowAndBadShapesAreRefused) {
  const CameraTarget grid = CameraTarget::grid(2, 3, 25);
  ASSERT_EQ(grid.points.size(), 6u);
  EXPECT_EQ(grid.points[4], Vector3d(25, 25, 0));  // row 1, column 1
  EXPECT_EQ(grid.names[5], "p5");
  EXPECT_THROW(CameraTarget::grid(1, 5, 25), std::invalid_argument);
  EXPECT_THROW(CameraTarget::grid(3, 3, 0), std::invalid_argument);
  EXPECT_THROW(CameraTarget::from_points({Vector3d::Zero(), Vector3d::Ones()}),
               std::invalid_argument);
}

// A model file: the ur5-urdf arm with this camera as its only sensor.
std::string camera_model(const std::string& camera_object) {
  const auto arm = make_preset("ur5-urdf");
  nlohmann::ordered_json j = model_to_json(*arm, arm->parameters().nominal_values());
  j["sensors"] = nlohmann::ordered_json::array({nlohmann::ordered_json::parse(camera_object)});
  j["free"] = nlohmann::ordered_json::array();
  return j.dump(2);
}

TEST(CameraModelFile, ReadsAndWritesBackAGridAndAPointsTarget) {
  for (const std::string target :
       {R"("grid": {"rows": 4, "columns": 5, "spacing": 30})",
        R"("points": [[0, 0, 0], [50, 0, 0], [0, 50, 0], [50, 50, 10]])"}) {
    const std::string text = camera_model(
        R"({"type": "camera", "name": "cam", "mounting": "eye-to-hand",
            "image": {"width": 1280, "height": 1024},
            "frame": {"position": [0, 0, 1500], "rotation_zyx_deg": [180, 0, 0]},
            "target": {"frame": {"position": [-60, -45, 10], "rotation_zyx_deg": [0, 0, 0]}, )" +
        target + R"(},
            "intrinsics": {"fx": 1200, "fy": 1201, "cx": 640, "cy": 512},
            "distortion": {"k1": -0.1, "k2": 0.05, "p1": 0.001}})");
    std::shared_ptr<MeasurementModel> model;
    try {
      model = model_from_text(text, "model.json");
    } catch (const std::exception& e) {
      FAIL() << e.what();
    }
    const auto& camera = dynamic_cast<const Camera&>(*model->sensors()[0]);
    EXPECT_EQ(camera.mounting(), CameraMounting::kEyeToHand);
    const ParameterSet& p = model->parameters();
    EXPECT_DOUBLE_EQ(p[p.index_of("cam.fy")].nominal, 1201);
    EXPECT_DOUBLE_EQ(p[p.index_of("cam.k3")].nominal, 0);
    EXPECT_DOUBLE_EQ(p[p.index_of("cam.p1")].nominal, 0.001);
    const std::string written = model_to_json(*model, model->parameters().nominal_values()).dump(2);
    const auto again = model_from_text(written, "again.json");
    EXPECT_EQ(model_to_json(*again, again->parameters().nominal_values()).dump(2), written);
    EXPECT_EQ(dynamic_cast<const Camera&>(*again->sensors()[0]).target().points,
              camera.target().points);
  }
}

TEST(CameraModelFile, BadInputIsOneLineNamingTheKey) {
  const std::string good_target =
      R"("target": {"frame": {"position": [0, 0, 0], "rotation_zyx_deg": [0, 0, 0]},
                    "grid": {"rows": 4, "columns": 5, "spacing": 30}})";
  const std::string common =
      R"("type": "camera", "name": "cam", "image": {"width": 1280, "height": 1024},
         "frame": {"position": [0, 0, 1500], "rotation_zyx_deg": [180, 0, 0]},
         "intrinsics": {"fx": 1200, "fy": 1200, "cx": 640, "cy": 512})";
  const std::pair<std::string, std::string> cases[] = {
      {"{" + common + R"(, "mounting": "on-the-wall", )" + good_target + "}", "mounting"},
      {"{" + common + R"(, "mounting": "eye-in-hand", "target": {"frame": {"position": [0, 0, 0],
          "rotation_zyx_deg": [0, 0, 0]}})" +
           "}",
       "either \"grid\""},
      {"{" + common + R"(, "mounting": "eye-in-hand", "target": {"frame": {"position": [0, 0, 0],
          "rotation_zyx_deg": [0, 0, 0]}, "grid": {"rows": 1, "columns": 5, "spacing": 30}})" +
           "}",
       "rows"},
      {"{" + common + R"(, "mounting": "eye-in-hand", "target": {"frame": {"position": [0, 0, 0],
          "rotation_zyx_deg": [0, 0, 0]}, "points": [[0, 0, 0], [1, 1, 1]]})" +
           "}",
       "at least 4 points"},
  };
  for (const auto& [object, expected] : cases) {
    try {
      model_from_text(camera_model(object), "model.json");
      ADD_FAILURE() << "accepted: " << object;
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("model.json"), std::string::npos) << what;
      EXPECT_NE(what.find(expected), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
}

}  // namespace
}  // namespace kincal
