// The pre-solve identifiability check of calibrate and simulate analyses the readings
// present and the constraint rows, as the report does: a missing reading is a zero row of
// the Jacobian and must not count as a residual.

#include <gtest/gtest.h>

#include <cmath>

#include "kincal/framework/analysis/identifiability_check.hpp"
#include "kincal/framework/calibration/constrained_problem.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/models/model_io.hpp"

namespace kincal {
namespace {

// The ur5-urdf arm with two sockets 50 mm apart and the fixture distance between them; each
// configuration has the tool in one socket, so half of the six readings are missing.
std::shared_ptr<const MeasurementModel> two_socket_model() {
  const auto preset = ModelRegistry::global().make_preset("ur5-urdf-socket");
  Json j = model_to_json(*preset, preset->parameters().nominal_values());
  j["sensors"] =
      Json::array({{{"type", "socket"}, {"name", "socket0"}, {"point", {-400.0, -100.0, 300.0}}},
                   {{"type", "socket"}, {"name", "socket1"}, {"point", {-400.0, -51.0, 310.0}}}});
  j["constraints"] = Json::array({{{"type", "fixture-distance"},
                                   {"between", {"socket0", "socket1"}},
                                   {"distance", 50.0},
                                   {"std", 0.05}}});
  j["free"] = Json::array({"socket*", "tool.x", "tool.y", "tool.z"});
  return model_from_json(j, "m.json");
}

Measurements socket_data(const MeasurementModel& model, int m) {
  Measurements data;
  data.actuators.resize(m, model.mechanism().num_actuators());
  data.readings.setConstant(m, model.num_readings(), NAN);
  for (int c = 0; c < m; ++c) {
    for (int i = 0; i < data.actuators.cols(); ++i)
      data.actuators(c, i) = 0.4 * std::sin(1.1 * c + 2.0 * i + 0.3);
    data.readings.block(c, c < m / 2 ? 0 : 3, 1, 3).setZero();
  }
  return data;
}

TEST(IdentifiabilityCheck, AnalysesTheReadingsPresentAndTheConstraintRows) {
  const auto model = two_socket_model();
  const int m = 10;
  const CalibrationProblem problem(model, socket_data(*model, m),
                                   model->parameters().nominal_values(),
                                   model->parameters().free_indices());
  const VectorXd x = problem.initial_free_parameters();
  VectorXd r;
  MatrixXd J;
  ASSERT_TRUE(problem.evaluate(x, &r, &J));
  ASSERT_EQ(J.rows(), m * 6);
  append_constraint_rows(problem, x, J);
  ASSERT_EQ(J.rows(), m * 6 + 1);

  const IdentifiabilityCheck check = check_identifiability(
      "data.csv", problem, J, WhenRankDeficient::kStop, IdentifiabilityOptions{}, "fix parameters");
  // 3 readings per configuration and the constraint, not the 6 m + 1 rows of J.
  EXPECT_EQ(check.analysis.num_residuals, m * 3 + 1);
  // What remains is the same analysis as on those rows alone.
  std::vector<int> rows = problem.data().present_rows();
  rows.push_back(static_cast<int>(J.rows()) - 1);
  const Identifiability direct =
      analyze_identifiability(J(rows, Eigen::all), problem.parameter_names());
  EXPECT_EQ(check.analysis.rank_threshold, direct.rank_threshold);
  EXPECT_EQ(check.analysis.numerical_rank, direct.numerical_rank);
  EXPECT_NEAR((check.analysis.singular_values - direct.singular_values).norm(), 0,
              1e-12 * direct.singular_values[0]);
}

}  // namespace
}  // namespace kincal
