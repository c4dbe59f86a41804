// The fixture-distance constraint and the problem that adds parameter-only constraints once:
// values, Jacobians against central differences, the cost they add, the model file and its
// errors, and the report's entry.

#include <gtest/gtest.h>

#include <cmath>

#include "jacobian_check.hpp"
#include "kincal/framework/analysis/calibration_report.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/calibration/constrained_problem.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/models/fixture_distance.hpp"
#include "kincal/models/model_io.hpp"
#include "kincal/models/socket.hpp"
#include "kincal/models/urdf_arm.hpp"

namespace kincal {
namespace {

using kincal::testing::jacobians_match;
using kincal::testing::numerical_jacobian;

TEST(FixtureDistance, ResidualIsTheDistanceMinusTheKnownOne) {
  const FixtureDistance c("a", "b", 50, 0.05);
  VectorXd values(6), r(1);
  values << 0, 0, 0, 30, 40, 0;  // 50 apart
  c.evaluate(values, r, nullptr);
  EXPECT_NEAR(r[0], 0, 1e-12);
  values[4] = 40.5;
  c.evaluate(values, r, nullptr);
  EXPECT_NEAR(r[0], std::hypot(30.0, 40.5) - 50, 1e-12);
  EXPECT_EQ(c.parameter_names(), (std::vector<std::string>{"a.point.x", "a.point.y", "a.point.z",
                                                           "b.point.x", "b.point.y", "b.point.z"}));
  EXPECT_EQ(c.residual_std()[0], 0.05);
}

TEST(FixtureDistance, JacobianMatchesFiniteDifferences) {
  const FixtureDistance c("a", "b", 50, 0.05);
  Random rng(7);
  for (int trial = 0; trial < 5; ++trial) {
    VectorXd values(6);
    for (int i = 0; i < 6; ++i) values[i] = rng.symmetric(300);
    VectorXd r(1);
    MatrixXd J(1, 6);
    c.evaluate(values, r, &J);
    auto f = [&](const VectorXd& v) {
      VectorXd out(1);
      c.evaluate(v, out, nullptr);
      return out;
    };
    EXPECT_TRUE(jacobians_match(J, numerical_jacobian(f, values, 1e-5), 1e-7));
  }
}

TEST(FixtureDistance, RefusesWhatIsNoDistance) {
  EXPECT_THROW(FixtureDistance("a", "a", 50, 1), std::invalid_argument);
  EXPECT_THROW(FixtureDistance("a", "b", -1, 1), std::invalid_argument);
  EXPECT_THROW(FixtureDistance("a", "b", 50, 0), std::invalid_argument);
  EXPECT_THROW(FixtureDistance("a", "b", NAN, 1), std::invalid_argument);
}

// The ur5-urdf arm with two sockets 50 mm apart and the constraint between them, as a model
// file would give it.
Json two_socket_model_json() {
  const auto preset = ModelRegistry::global().make_preset("ur5-urdf-socket");
  Json j = model_to_json(*preset, preset->parameters().nominal_values());
  j["sensors"] =
      Json::array({{{"type", "socket"}, {"name", "socket0"}, {"point", {-400.0, -100.0, 300.0}}},
                   {{"type", "socket"}, {"name", "socket1"}, {"point", {-400.0, -51.0, 310.0}}}});
  j["constraints"] = Json::array({{{"type", "fixture-distance"},
                                   {"between", {"socket0", "socket1"}},
                                   {"distance", 50.0},
                                   {"std", 0.05}}});
  j["free"] = Json::array(
      {"socket*", "tool.x", "tool.y", "tool.z", "wrist_3_joint.offset", "elbow_joint.origin.x"});
  return j;
}

TEST(FixtureDistance, ModelFileRoundTrip) {
  const auto model = model_from_json(two_socket_model_json(), "m.json");
  ASSERT_EQ(model->constraints().size(), 1u);
  EXPECT_EQ(model->constraints()[0]->type(), "fixture-distance");
  EXPECT_EQ(model->constraint_parameter_indices(0).size(), 6u);
  EXPECT_EQ(model->parameters()[model->constraint_parameter_indices(0)[3]].name, "socket1.point.x");
  const Json written = model_to_json(*model, model->parameters().nominal_values());
  EXPECT_EQ(written["constraints"], two_socket_model_json()["constraints"]);
  const auto back = model_from_json(written, "back.json");
  EXPECT_EQ(back->constraints().size(), 1u);
}

void expect_one_line_error(const Json& j, const std::string& expected) {
  try {
    model_from_json(j, "m.json");
    FAIL() << "accepted; expected an error with '" << expected << "'";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(expected), std::string::npos) << what;
    EXPECT_EQ(what.rfind("m.json", 0), 0u) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

TEST(FixtureDistance, BadModelFilesFailOnOneLineNamingWhere) {
  Json j = two_socket_model_json();
  j["constraints"][0]["between"][1] = "socket7";
  expect_one_line_error(j, "constraints[0].between[1]");
  j = two_socket_model_json();
  j["constraints"][0]["std"] = 0;
  expect_one_line_error(j, "std > 0");
  j = two_socket_model_json();
  j["constraints"][0]["type"] = "fixture-angle";
  expect_one_line_error(j, "constraints[0].type");
  j = two_socket_model_json();
  j["constraints"][0]["distnce"] = 50;
  expect_one_line_error(j, "distnce");
  j = two_socket_model_json();
  j["constraints"][0].erase("distance");
  expect_one_line_error(j, "distance");
}

// Configurations of the arm with the tool in socket 0 (rows 0-3) or socket 1 (rows 4-7).
Measurements socket_data(const MeasurementModel& model) {
  Measurements data;
  data.actuators.resize(8, model.mechanism().num_actuators());
  data.readings.setConstant(8, model.num_readings(), NAN);
  for (int c = 0; c < 8; ++c) {
    for (int i = 0; i < data.actuators.cols(); ++i)
      data.actuators(c, i) = 0.4 * std::sin(1.1 * c + 2.0 * i + 0.3);
    data.readings.block(c, c < 4 ? 0 : 3, 1, 3).setZero();
  }
  return data;
}

TEST(ConstrainedProblem, AddsTheConstraintOnceWithItsJacobian) {
  const std::shared_ptr<const MeasurementModel> model =
      model_from_json(two_socket_model_json(), "m.json");
  const CalibrationProblem data(model, socket_data(*model), model->parameters().nominal_values(),
                                model->parameters().free_indices());
  const ConstrainedProblem problem(data);
  // 8 configurations of 6 readings, and one block holding the one constraint residual.
  EXPECT_EQ(problem.num_residual_blocks(), 9);
  VectorXd x = data.initial_free_parameters();
  Random rng(3);
  for (int i = 0; i < x.size(); ++i) x[i] += rng.symmetric(0.5);
  VectorXd r, r_data;
  MatrixXd J;
  ASSERT_TRUE(problem.evaluate(x, &r, &J));
  ASSERT_TRUE(data.evaluate(x, &r_data, nullptr));
  // The cost is the data's plus the whitened constraint's, and the padding is zero.
  const VectorXd full = data.full_parameters(x);
  const auto& idx = model->constraint_parameter_indices(0);
  const Vector3d a(full[idx[0]], full[idx[1]], full[idx[2]]);
  const Vector3d b(full[idx[3]], full[idx[4]], full[idx[5]]);
  const double expected = ((a - b).norm() - 50) / 0.05;
  EXPECT_NEAR(r[r_data.size()], expected, 1e-9 * (1 + std::abs(expected)));
  EXPECT_EQ(r.tail(r.size() - r_data.size() - 1).squaredNorm(), 0);
  EXPECT_NEAR(r.squaredNorm(), r_data.squaredNorm() + expected * expected, 1e-9 * r.squaredNorm());
  auto f = [&](const VectorXd& v) {
    VectorXd out;
    EXPECT_TRUE(problem.evaluate(v, &out, nullptr));
    return out;
  };
  EXPECT_TRUE(jacobians_match(J, numerical_jacobian(f, x, 1e-6), 1e-6));
}

TEST(ConstrainedProblem, ReportListsTheConstraintAndCountsItsRow) {
  const std::shared_ptr<const MeasurementModel> model =
      model_from_json(two_socket_model_json(), "m.json");
  const CalibrationProblem data(model, socket_data(*model), model->parameters().nominal_values(),
                                model->parameters().free_indices());
  const VectorXd x = data.initial_free_parameters();
  Summary summary;
  const std::vector<int> lines = {2, 3, 4, 5, 6, 7, 8, 9};
  const CalibrationReport report = make_calibration_report(data, x, summary, lines);
  ASSERT_EQ(report.constraints.size(), 1u);
  // The model file's sockets are sqrt(49^2 + 10^2) apart.
  EXPECT_NEAR(report.constraints[0].residual, std::hypot(49.0, 10.0) - 50, 1e-9);
  EXPECT_EQ(report.constraints[0].unit, "mm");
  // 24 measured readings and the constraint: the degrees of freedom count its row.
  EXPECT_EQ(report.uncertainty.degrees_of_freedom, 24 + 1 - static_cast<int>(x.size()));
  const auto json = to_json(report);
  ASSERT_TRUE(json.contains("constraints"));
  EXPECT_EQ(json["constraints"][0]["label"], "|socket0 - socket1| = 50 mm");
  EXPECT_NE(to_text(report).find("constraint fixture-distance |socket0 - socket1| = 50 mm"),
            std::string::npos);
}

}  // namespace
}  // namespace kincal
