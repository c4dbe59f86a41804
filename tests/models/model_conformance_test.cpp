// The conformance suite over models: every preset of ModelRegistry::global(), hence every
// registered mechanism and sensor type (each must appear in a preset), is held to the checks
// of models/conformance.hpp, the same code `kincal check` runs on a plug-in's types:
//   - its model file round-trips exactly, and every unit is declared;
//   - every analytic Jacobian against central finite differences (the mechanism's
//     J_pose_params and d pose / d q, each sensor's J_reading_pose and J_reading_params, the
//     calibration residuals' Jacobian);
//   - inverse kinematics of forward kinematics returns to the same pose;
//   - zero-noise recovery: from the nominal geometry, every least-squares backend reaches
//     the true value of every free parameter within 1e-6 (of its unit).
// A new registration is tested by registering it; a preset that fails here is not usable.

#include <gtest/gtest.h>

#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/conformance.hpp"

namespace kincal {
namespace {

std::vector<std::string> preset_names() {
  std::vector<std::string> names;
  for (const auto& p : ModelRegistry::global().presets()) names.push_back(p.name);
  return names;
}

std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string name = info.param;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

ModelFactory preset(const std::string& name) {
  return [name] { return ModelRegistry::global().make_preset(name); };
}

void expect_all_pass(const std::vector<ConformanceCheck>& checks) {
  ASSERT_FALSE(checks.empty()) << "no check ran";
  for (const auto& c : checks)
    EXPECT_TRUE(c.passed) << c.name << ": worst " << c.worst << " (tolerance " << c.tolerance
                          << "), " << c.detail;
}

TEST(ModelRegistry, EveryMechanismAndSensorTypeHasAPreset) {
  expect_all_pass(check_registry_coverage(ModelRegistry::global()));
}

TEST(ModelRegistry, UnknownNamesListTheRegisteredOnes) {
  try {
    ModelRegistry::global().make_preset("no-such-robot");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cube-hexapod"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ModelRegistry::global().mechanism("no-such-mechanism"), std::invalid_argument);
  EXPECT_THROW(ModelRegistry::global().sensor("no-such-sensor"), std::invalid_argument);
}

TEST(ModelRegistry, RegisteringANameTwiceIsAnError) {
  ModelRegistry registry;
  register_builtin_models(registry);
  EXPECT_THROW(registry.add_preset(registry.presets().front()), std::logic_error);
  EXPECT_THROW(registry.add_mechanism(registry.mechanisms().front()), std::logic_error);
  EXPECT_THROW(registry.add_sensor(registry.sensors().front()), std::logic_error);
}

// The checker itself must be able to fail: a Jacobian with one sign flipped, and one of the
// wrong size, are failures that say where.
TEST(ConformanceChecker, ComparisonNamesTheWorstEntry) {
  MatrixXd numeric(2, 3);
  numeric << 1, 2, 3, 4, 5, 6;
  MatrixXd flipped = numeric;
  flipped(1, 2) = -6;
  const auto bad = compare_jacobians("J", flipped, numeric, 1e-6, {"a", "b", "c"});
  EXPECT_FALSE(bad.passed);
  EXPECT_NEAR(bad.worst, 12.0 / 7.0, 1e-12);
  EXPECT_NE(bad.detail.find("row 1, column 2 'c'"), std::string::npos) << bad.detail;
  EXPECT_TRUE(compare_jacobians("J", numeric, numeric, 1e-6).passed);
  EXPECT_FALSE(compare_jacobians("J", numeric.leftCols(2), numeric, 1e-6).passed);
  MatrixXd with_nan = numeric;
  with_nan(0, 0) = std::nan("");
  EXPECT_FALSE(compare_jacobians("J", with_nan, numeric, 1e-6).passed);
}

class PresetConformance : public ::testing::TestWithParam<std::string> {};

TEST_P(PresetConformance, ModelFileRoundTripsAndUnitsAreDeclared) {
  expect_all_pass(check_model_file(preset(GetParam())));
}

TEST_P(PresetConformance, MechanismJacobiansMatchFiniteDifferences) {
  expect_all_pass(check_mechanism_jacobians(preset(GetParam())));
}

TEST_P(PresetConformance, SensorJacobiansMatchFiniteDifferences) {
  expect_all_pass(check_sensor_jacobians(preset(GetParam())));
}

TEST_P(PresetConformance, ResidualJacobianMatchesFiniteDifferences) {
  expect_all_pass(check_residual_jacobian(preset(GetParam())));
}

TEST_P(PresetConformance, InverseKinematicsReturnsToTheForwardKinematicsPose) {
  expect_all_pass(check_inverse_kinematics(preset(GetParam())));
}

TEST_P(PresetConformance, EveryLeastSquaresBackendRecoversTheTruthWithoutNoise) {
  expect_all_pass(check_recovery(preset(GetParam()), SolverRegistry::global()));
}

INSTANTIATE_TEST_SUITE_P(Presets, PresetConformance, ::testing::ValuesIn(preset_names()),
                         test_name);

}  // namespace
}  // namespace kincal
