// run_calibration's iteration tracking and the caller's own callback.

#include "kincal/framework/calibration/simulation.hpp"

#include <gtest/gtest.h>

#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/presets.hpp"

namespace kincal {
namespace {

Scenario small_scenario() {
  ScenarioOptions options;
  options.num_configurations = 30;
  options.num_validation = 5;
  options.seed = 3;
  return make_scenario(make_cube_hexapod(), options);
}

// The tracking callback wraps the caller's one. It used to refer to a copy that had gone out
// of scope by the time the solver called it (stack-use-after-scope under AddressSanitizer,
// in every simulate and reproduce run).
TEST(Simulation, TrackingCallsTheCallersCallbackAtEveryIteration) {
  const Scenario scenario = small_scenario();
  const auto solver = SolverRegistry::global().create("gn");
  SolverOptions options;
  int calls = 0;
  options.callback = [&calls](const IterationRecord& record, const VectorXd&) {
    ++calls;
    return record.iteration >= 2 ? CallbackAction::kStop : CallbackAction::kContinue;
  };
  const CalibrationRun run = run_calibration(scenario, *solver, options, true);
  EXPECT_EQ(run.summary.termination, TerminationType::kUserStopped) << run.summary.brief_report();
  EXPECT_EQ(calls, 3);  // iterations 0, 1 and 2
  EXPECT_EQ(run.trace_errors.size(), run.summary.trace.size());
  EXPECT_EQ(run.summary.trace.size(), 3u);
}

// A known truth (simulate --truth): used as given, not drawn; a vector that does not fit the
// model is refused.
TEST(Simulation, AGivenTruthIsUsedAsGiven) {
  const auto model = make_cube_hexapod();
  ScenarioOptions options;
  options.num_configurations = 30;
  options.num_validation = 5;
  options.truth = model->parameters().nominal_values();
  options.truth[0] += 1.5;
  const Scenario s = make_scenario(model, options);
  EXPECT_EQ(s.truth, options.truth);
  options.truth.resize(3);
  EXPECT_THROW(make_scenario(model, options), std::invalid_argument);
}

}  // namespace
}  // namespace kincal

namespace kincal {
namespace {

// The planned configurations must match num_configurations and the model's columns; the
// error names the size that differs (issue 22: the doc comment and the code disagreed).
TEST(Simulation, PlannedConfigurationsOfTheWrongSizeNameWhatDiffers) {
  const auto model = make_cube_hexapod();
  ScenarioOptions options;
  options.seed = 3;
  options.num_configurations = 4;
  options.planned.actuators = MatrixXd::Constant(4, 6, 0.0);
  options.planned.readings = MatrixXd::Zero(4, 1);
  VectorXd q(6);
  model->mechanism().home_actuators(
      model->parameters().nominal_values().head(model->mechanism().num_parameters()), q);
  for (int r = 0; r < 4; ++r) options.planned.actuators.row(r) = q.transpose();
  EXPECT_NO_THROW(make_scenario(model, options));
  const auto message = [&](const ScenarioOptions& o) {
    try {
      make_scenario(model, o);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  ScenarioOptions rows = options;
  rows.num_configurations = 5;
  EXPECT_EQ(message(rows), "the planned configurations have 4 rows, expected 5");
  ScenarioOptions readings = options;
  readings.planned.readings = MatrixXd::Zero(4, 2);
  EXPECT_EQ(message(readings), "the planned configurations have 2 reading columns, expected 1");
}

}  // namespace
}  // namespace kincal

namespace kincal {
namespace {

// Configurations are drawn in batches whose forward kinematics runs on all cores from two
// batches (8192 configurations) on; they must be those of a one-by-one draw, so a large
// scenario begins with the configurations, readings and truth of a small one of the same seed.
TEST(Simulation, ALargeScenarioBeginsWithTheSmallOneOfTheSameSeed) {
  ScenarioOptions options;
  options.noise_half_width.set(kincal::kMillimetre, 0.0125);
  options.num_validation = 3;
  options.seed = 21;
  options.num_configurations = 60;
  const Scenario small = make_scenario(make_cube_hexapod(), options);
  options.num_configurations = 9000;
  const Scenario large = make_scenario(make_cube_hexapod(), options);
  EXPECT_EQ(small.truth, large.truth);
  EXPECT_EQ(small.calibration.actuators, large.calibration.actuators.topRows(60));
  EXPECT_EQ(small.calibration.readings, large.calibration.readings.topRows(60));
  EXPECT_EQ(small.validation_actuators, large.validation_actuators);
}

}  // namespace
}  // namespace kincal
