// The socket sensor: its reading is the tool point minus the socket's centre, its Jacobians
// against central differences, and its model-file form.

#include <gtest/gtest.h>

#include "jacobian_check.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/models/model_io.hpp"
#include "kincal/models/socket.hpp"

namespace kincal {
namespace {

using kincal::testing::jacobians_match;
using kincal::testing::numerical_jacobian;

TEST(Socket, ReadsTheToolPointRelativeToTheSocket) {
  const Socket socket("socket0", Vector3d(100, -20, 300));
  Pose pose;
  pose.translation = Vector3d(110, -25, 330);
  pose.rotation = exp_so3(Vector3d(0.3, -0.2, 0.5));
  VectorXd params(3), reading(3);
  params << 100, -20, 300;
  socket.predict(params, pose, reading, nullptr, nullptr);
  EXPECT_NEAR((reading - Vector3d(10, -5, 30)).norm(), 0, 1e-12);
  EXPECT_EQ(socket.reading_names(),
            (std::vector<std::string>{"socket0.x", "socket0.y", "socket0.z"}));
  EXPECT_EQ(socket.parameters()[2].name, "socket0.point.z");
  EXPECT_EQ(socket.parameters()[2].unit, "mm");
}

TEST(Socket, JacobiansMatchFiniteDifferences) {
  const Socket socket("s", Vector3d(1, 2, 3));
  Random rng(24);
  for (int trial = 0; trial < 5; ++trial) {
    Vector6d delta;
    for (int i = 0; i < 6; ++i) delta[i] = rng.symmetric(i < 3 ? 500 : 2);
    const Pose pose = perturb(Pose{}, delta);
    VectorXd params(3);
    for (int i = 0; i < 3; ++i) params[i] = rng.symmetric(400);
    VectorXd reading(3);
    MatrixXd J_pose(3, 6), J_params(3, 3);
    socket.predict(params, pose, reading, &J_pose, &J_params);
    auto by_pose = [&](const VectorXd& d) {
      VectorXd r(3);
      socket.predict(params, perturb(pose, d), r, nullptr, nullptr);
      return r;
    };
    auto by_params = [&](const VectorXd& p) {
      VectorXd r(3);
      socket.predict(p, pose, r, nullptr, nullptr);
      return r;
    };
    EXPECT_TRUE(
        jacobians_match(J_pose, numerical_jacobian(by_pose, VectorXd::Zero(6), 1e-6), 1e-7));
    EXPECT_TRUE(jacobians_match(J_params, numerical_jacobian(by_params, params, 1e-6), 1e-7));
  }
}

TEST(Socket, ModelFileRoundTrip) {
  const auto model = ModelRegistry::global().make_preset("ur5-urdf-socket");
  const VectorXd values = model->parameters().nominal_values();
  const Json j = model_to_json(*model, values);
  const Json& sensor = j["sensors"][0];
  EXPECT_EQ(sensor["type"], "socket");
  ASSERT_TRUE(sensor.contains("point"));
  EXPECT_EQ(sensor["point"].size(), 3u);
  const auto back = model_from_json(j, "round-trip");
  EXPECT_EQ(back->parameters().nominal_values(), values);
  EXPECT_EQ(back->parameters().free_indices(), model->parameters().free_indices());
}

TEST(Socket, BadPointIsOneLineNamingWhere) {
  Json j = model_to_json(
      *ModelRegistry::global().make_preset("ur5-urdf-socket"),
      ModelRegistry::global().make_preset("ur5-urdf-socket")->parameters().nominal_values());
  j["sensors"][0]["point"] = {1, 2};
  try {
    model_from_json(j, "m.json");
    FAIL() << "a two-element point was accepted";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("m.json"), std::string::npos) << what;
    EXPECT_NE(what.find("point"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace kincal
