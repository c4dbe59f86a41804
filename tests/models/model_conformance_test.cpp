// The conformance suite over models: every preset of ModelRegistry::global(), hence every
// registered mechanism and sensor type (each must appear in a preset), is held to the same
// checks without a line of test code of its own:
//   - its model file round-trips exactly;
//   - every analytic Jacobian against central finite differences, at configurations drawn
//     as a simulation draws them: the mechanism's J_pose_params, each sensor's
//     J_reading_pose and J_reading_params, the calibration residuals' Jacobian, and the
//     mechanism's d pose / d q;
//   - inverse kinematics of forward kinematics returns to the same pose;
//   - zero-noise recovery: from the nominal geometry, every least-squares backend reaches
//     the true value of every free parameter within 1e-6 (of its unit).
// A new registration is tested by registering it; a preset that fails here is not usable.

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "jacobian_check.hpp"
#include "kincal/framework/model_registry.hpp"
#include "kincal/framework/simulation.hpp"
#include "kincal/framework/solver_registry.hpp"
#include "kincal/framework/units.hpp"
#include "kincal/models/model_io.hpp"

namespace kincal {
namespace {

using kincal::testing::jacobians_match;
using kincal::testing::numerical_jacobian;

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

// A noise-free scenario of the preset as `kincal simulate --preset` draws it.
Scenario scenario_of(const std::string& preset, std::uint64_t seed, int validation = 0) {
  ScenarioOptions options;
  options.num_validation = validation;
  options.seed = seed;
  return make_scenario(ModelRegistry::global().make_preset(preset), options);
}

// [t1 - t0; log(R1 R0^T)]: the perturbation taking pose `from` to pose `to` (pose.hpp).
Vector6d pose_difference(const Pose& from, const Pose& to) {
  Vector6d d;
  d << to.translation - from.translation, log_so3(to.rotation * from.rotation.transpose());
  return d;
}

TEST(ModelRegistry, EveryMechanismAndSensorTypeHasAPreset) {
  std::set<std::string> mechanisms, sensors;
  for (const auto& p : ModelRegistry::global().presets()) {
    const auto model = p.make();
    mechanisms.insert(model->mechanism().type());
    for (const auto& s : model->sensors()) sensors.insert(s->type());
    EXPECT_GT(model->parameters().num_free(), 0) << p.name << " frees no parameter";
    EXPECT_FALSE(p.description.empty()) << p.name << ": describe it and cite its source";
  }
  for (const auto& t : ModelRegistry::global().mechanisms())
    EXPECT_TRUE(mechanisms.count(t.type)) << "mechanism type " << t.type << " is in no preset";
  for (const auto& t : ModelRegistry::global().sensors())
    EXPECT_TRUE(sensors.count(t.type)) << "sensor type " << t.type << " is in no preset";
}

TEST(ModelRegistry, UnknownNamesListTheRegisteredOnes) {
  try {
    ModelRegistry::global().make_preset("no-such-robot");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cube-hexapod"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ModelRegistry::global().mechanism("delta"), std::invalid_argument);
  EXPECT_THROW(ModelRegistry::global().sensor("laser"), std::invalid_argument);
}

TEST(ModelRegistry, RegisteringANameTwiceIsAnError) {
  ModelRegistry registry;
  register_builtin_models(registry);
  EXPECT_THROW(registry.add_preset(registry.presets().front()), std::logic_error);
  EXPECT_THROW(registry.add_mechanism(registry.mechanisms().front()), std::logic_error);
  EXPECT_THROW(registry.add_sensor(registry.sensors().front()), std::logic_error);
}

class PresetConformance : public ::testing::TestWithParam<std::string> {};

TEST_P(PresetConformance, ModelFileRoundTripsExactly) {
  const auto model = ModelRegistry::global().make_preset(GetParam());
  const VectorXd values = model->parameters().nominal_values();
  const Json first = model_to_json(*model, values);
  const auto back = model_from_json(first, "(round trip)");
  EXPECT_EQ(model_to_json(*back, back->parameters().nominal_values()).dump(), first.dump());
  ASSERT_EQ(back->num_parameters(), model->num_parameters());
  for (int i = 0; i < model->num_parameters(); ++i) {
    const Parameter &a = (*model).parameters()[i], &b = back->parameters()[i];
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.unit, b.unit) << a.name;
    EXPECT_EQ(a.free, b.free) << a.name;
    // Angles pass through degrees in the file: equal to rounding.
    EXPECT_NEAR(a.nominal, b.nominal, 1e-12 * (1 + std::abs(a.nominal))) << a.name;
  }
  EXPECT_EQ(back->mechanism().actuator_names(), model->mechanism().actuator_names());
  EXPECT_EQ(back->reading_names(), model->reading_names());
}

TEST_P(PresetConformance, UnitsAreDeclaredEverywhere) {
  const auto model = ModelRegistry::global().make_preset(GetParam());
  for (const auto& p : model->parameters().all())
    EXPECT_TRUE(is_known_unit(p.unit)) << p.name << " has unit '" << p.unit << "'";
  for (const auto& a : model->mechanism().actuators()) {
    EXPECT_TRUE(is_known_unit(a.unit)) << a.name << " has unit '" << a.unit << "'";
    EXPECT_GT(a.default_range, 0) << a.name;
  }
  const auto units = model->reading_units();
  ASSERT_EQ(static_cast<int>(units.size()), model->num_readings());
  for (const auto& u : units) EXPECT_TRUE(is_known_unit(u)) << u;
}

TEST_P(PresetConformance, PoseJacobianMatchesFiniteDifferences) {
  const Scenario s = scenario_of(GetParam(), 3);
  const Mechanism& mechanism = s.model->mechanism();
  const VectorXd params = s.truth.head(mechanism.num_parameters());
  const auto fk_options = s.model->forward_kinematics_options();
  for (int j = 0; j < std::min(4, s.calibration.size()); ++j) {
    const VectorXd q = s.calibration.actuators.row(j).transpose();
    const auto fk = mechanism.forward_kinematics(params, q, mechanism.home_pose(), fk_options);
    ASSERT_TRUE(fk.ok()) << fk.describe();
    Matrix6Xd J(6, mechanism.num_parameters());
    mechanism.pose_jacobian_params(params, q, fk.pose, J);
    auto pose_at = [&](const VectorXd& p) -> VectorXd {
      const auto moved = mechanism.forward_kinematics(p, q, mechanism.home_pose(), fk_options);
      EXPECT_TRUE(moved.ok()) << moved.describe();
      return pose_difference(fk.pose, moved.pose);
    };
    EXPECT_TRUE(jacobians_match(J, numerical_jacobian(pose_at, params, 1e-6), 1e-6,
                                s.model->parameters().names()))
        << "configuration " << j;
  }
}

// d pose / d q (experiment design's singularity margin): the closed chains' implicit-function
// form and the default's differences of forward kinematics, against central differences
// with another step.
TEST_P(PresetConformance, ActuatorJacobianMatchesFiniteDifferences) {
  const Scenario s = scenario_of(GetParam(), 5);
  const Mechanism& mechanism = s.model->mechanism();
  const VectorXd params = s.truth.head(mechanism.num_parameters());
  const auto fk_options = s.model->forward_kinematics_options();
  for (int j = 0; j < std::min(4, s.calibration.size()); ++j) {
    const VectorXd q = s.calibration.actuators.row(j).transpose();
    const auto fk = mechanism.forward_kinematics(params, q, mechanism.home_pose(), fk_options);
    ASSERT_TRUE(fk.ok()) << fk.describe();
    Matrix6Xd J(6, mechanism.num_actuators());
    ASSERT_TRUE(mechanism.pose_jacobian_actuators(params, q, fk.pose, fk_options, J));
    auto pose_at = [&](const VectorXd& moved_q) -> VectorXd {
      const auto moved = mechanism.forward_kinematics(params, moved_q, fk.pose, fk_options);
      EXPECT_TRUE(moved.ok()) << moved.describe();
      return pose_difference(fk.pose, moved.pose);
    };
    EXPECT_TRUE(
        jacobians_match(J, numerical_jacobian(pose_at, q, 1e-5), 1e-6, mechanism.actuator_names()))
        << "configuration " << j;
  }
}

TEST_P(PresetConformance, SensorJacobiansMatchFiniteDifferences) {
  const Scenario s = scenario_of(GetParam(), 4);
  const Mechanism& mechanism = s.model->mechanism();
  for (std::size_t k = 0; k < s.model->sensors().size(); ++k) {
    const Sensor& sensor = *s.model->sensors()[k];
    const int n = sensor.num_readings();
    const VectorXd params = s.truth.segment(s.model->sensor_parameter_offset(static_cast<int>(k)),
                                            sensor.num_parameters());
    const auto fk = mechanism.forward_kinematics(
        s.truth.head(mechanism.num_parameters()), s.calibration.actuators.row(0).transpose(),
        mechanism.home_pose(), s.model->forward_kinematics_options());
    ASSERT_TRUE(fk.ok());
    VectorXd reading(n);
    MatrixXd J_pose(n, 6), J_params(n, sensor.num_parameters());
    sensor.predict(params, fk.pose, reading, &J_pose, &J_params);
    // Differences are taken as the sensor's own reading error (tangent space for manifold
    // readings), the space its Jacobian rows live in.
    auto error_from_reading = [&](const VectorXd& other) -> VectorXd {
      VectorXd e(n);
      sensor.reading_error(other, reading, e, nullptr);
      return e;
    };
    auto at_params = [&](const VectorXd& p) {
      VectorXd r(n);
      sensor.predict(p, fk.pose, r, nullptr, nullptr);
      return error_from_reading(r);
    };
    auto at_pose = [&](const VectorXd& delta) {
      VectorXd r(n);
      sensor.predict(params, perturb(fk.pose, delta), r, nullptr, nullptr);
      return error_from_reading(r);
    };
    EXPECT_TRUE(jacobians_match(J_params, numerical_jacobian(at_params, params, 1e-6), 1e-6))
        << sensor.name() << ": J_reading_params";
    EXPECT_TRUE(jacobians_match(J_pose, numerical_jacobian(at_pose, VectorXd::Zero(6), 1e-6), 1e-6))
        << sensor.name() << ": J_reading_pose";
  }
}

TEST_P(PresetConformance, ResidualJacobianMatchesFiniteDifferences) {
  // The Jacobian every solver uses: through forward kinematics, the sensors and their
  // reading errors, with the data measured at the truth and the parameters at nominal.
  const Scenario s = scenario_of(GetParam(), 5);
  const auto problem = s.make_problem();
  const VectorXd x = problem->initial_free_parameters();
  VectorXd r;
  MatrixXd J;
  std::string why;
  ASSERT_TRUE(problem->evaluate(x, &r, &J, &why)) << why;
  auto residuals_at = [&](const VectorXd& p) {
    VectorXd out;
    EXPECT_TRUE(problem->evaluate(p, &out, nullptr, &why)) << why;
    return out;
  };
  EXPECT_TRUE(jacobians_match(J, numerical_jacobian(residuals_at, x, 1e-6), 1e-6,
                              problem->parameter_names()));
}

TEST_P(PresetConformance, InverseKinematicsReturnsToTheForwardKinematicsPose) {
  const Scenario s = scenario_of(GetParam(), 6);
  const Mechanism& mechanism = s.model->mechanism();
  const VectorXd params = s.truth.head(mechanism.num_parameters());
  const auto fk_options = s.model->forward_kinematics_options();
  VectorXd q(mechanism.num_actuators());
  for (int j = 0; j < s.calibration.size(); ++j) {
    const auto fk = mechanism.forward_kinematics(params, s.calibration.actuators.row(j).transpose(),
                                                 mechanism.home_pose(), fk_options);
    ASSERT_TRUE(fk.ok()) << fk.describe();
    const auto ik = mechanism.inverse_kinematics(params, fk.pose, q);
    ASSERT_TRUE(ik.ok()) << "configuration " << j << ": " << ik.describe();
    const auto back = mechanism.forward_kinematics(params, q, mechanism.home_pose(), fk_options);
    ASSERT_TRUE(back.ok()) << back.describe();
    EXPECT_LT(pose_difference(fk.pose, back.pose).norm(), 1e-8) << "configuration " << j;
  }
}

TEST_P(PresetConformance, EveryLeastSquaresBackendRecoversTheTruthWithoutNoise) {
  const SolverRegistry& solvers = SolverRegistry::global();
  for (const auto& info : solvers.list()) {
    if (info.kind != SolverKind::kLeastSquares) continue;
    for (const auto& name : info.variants) {
      for (std::uint64_t seed : {1, 2}) {
        const Scenario s = scenario_of(GetParam(), seed);
        const auto solver = solvers.create(name);
        const CalibrationRun run = run_calibration(s, *solver, SolverOptions{}, false);
        EXPECT_EQ(run.summary.termination, TerminationType::kConverged)
            << name << " seed " << seed << ": " << run.summary.message;
        for (int i : s.free_indices) {
          const Parameter& p = s.model->parameters()[i];
          double d = run.estimate[i] - s.truth[i];
          if (p.unit == kRadian) d = wrap_angle(d);
          EXPECT_LT(std::abs(d), 1e-6)
              << name << " seed " << seed << ": " << p.name << " (" << p.unit << ") off by " << d;
        }
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Presets, PresetConformance, ::testing::ValuesIn(preset_names()),
                         test_name);

}  // namespace
}  // namespace kincal
