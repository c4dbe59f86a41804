// Real-arm data (issue 20): unit suffixes and the wrong-unit check for every registered
// serial-arm preset, the home_pose check only for closed chains, outlier flags calibrated on
// clean Gaussian data, the noise estimate under a robust loss, the 3-D position error, the
// registration-only baseline and cross-validation. Every random draw has an explicit seed.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "kincal/framework/analysis/calibration_report.hpp"
#include "kincal/framework/analysis/cross_validation.hpp"
#include "kincal/framework/analysis/position_error.hpp"
#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/calibration/data_checks.hpp"
#include "kincal/framework/calibration/measurement_file.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/presets.hpp"

namespace kincal {
namespace {

std::vector<std::string> serial_arm_presets() {
  std::vector<std::string> names;
  for (const auto& p : list_presets())
    if (make_preset(p.name)->mechanism().type() == "serial-arm") names.push_back(p.name);
  return names;
}

// Configurations of `model` (seed), readings exact at the nominal values; the actuators
// spread over +-`range_rad` around home so that a joint in degrees goes beyond one turn.
Scenario scenario(const std::shared_ptr<MeasurementModel>& model, int configurations,
                  std::uint64_t seed, double param_error_mm = 0, double param_error_rad = 0) {
  ScenarioOptions o;
  o.num_configurations = configurations;
  o.param_error_half_width.set(kincal::kMillimetre, param_error_mm);
  o.param_error_half_width.set(kincal::kRadian, param_error_rad);
  o.num_validation = 0;
  o.seed = seed;
  return make_scenario(model, o);
}

// The CSV of `data` with the actuator columns multiplied by `scale` and named with `suffix`.
std::string csv(const MeasurementModel& model, Measurements data, double scale,
                const std::string& suffix) {
  data.actuators *= scale;
  std::vector<std::string> names = model.mechanism().actuator_names();
  for (auto& n : names) n += suffix;
  return measurements_to_csv(data, names, model.reading_names());
}

MeasurementTable read(const MeasurementModel& model, const std::string& text) {
  std::istringstream in(text);
  MeasurementTable table =
      parse_measurements(in, "D.csv", model.mechanism().actuator_names(), model.reading_names());
  std::vector<std::string> units;
  for (const auto& a : model.mechanism().actuators()) units.push_back(a.unit);
  convert_column_units(table, units, model.reading_units(), "D.csv");
  return table;
}

TEST(UnitSuffix, ColumnsInDegreesAndMetresAreConvertedOnReading) {
  const auto model = make_preset("puma560");
  const Scenario s = scenario(model, 10, 3);
  Measurements metres = s.calibration;
  metres.readings /= 1000;
  std::vector<std::string> actuators, readings;
  for (const auto& n : model->mechanism().actuator_names()) actuators.push_back(n + "_deg");
  for (const auto& n : model->reading_names()) readings.push_back(n + "_m");
  Measurements degrees = metres;
  degrees.actuators *= 180 / kPi;
  const MeasurementTable table = read(*model, measurements_to_csv(degrees, actuators, readings));
  EXPECT_EQ(table.column_units.front(), "deg");
  EXPECT_EQ(table.column_units.back(), "m");
  EXPECT_LT((table.data.actuators - s.calibration.actuators).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((table.data.readings - s.calibration.readings).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_EQ(check_data_units(*model, model->parameters().nominal_values(), table), "");
}

TEST(UnitSuffix, AWrongKindOfSuffixOrAColumnGivenTwiceIsAnError) {
  const auto model = make_preset("puma560");
  const Scenario s = scenario(model, 3, 3);
  try {
    read(*model, csv(*model, s.calibration, 1, "_mm"));
    FAIL() << "an angle in mm was read";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("joint1_mm"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("_rad or _deg"), std::string::npos) << e.what();
  }
  std::istringstream twice("joint1,joint1_deg\n1,2\n");
  EXPECT_THROW(parse_measurements(twice, "D.csv", {"joint1"}, {}), std::invalid_argument);
}

// Done-when of issue 20 item 3, for every registered serial-arm preset: degrees without a
// suffix are an error before solving; with _deg they read as the radians themselves.
TEST(DataUnits, JointDegreesWithoutSuffixAreAnErrorForEverySerialArmPreset) {
  const auto presets = serial_arm_presets();
  ASSERT_GE(presets.size(), 2u);
  for (const auto& name : presets) {
    const auto model = make_preset(name);
    const VectorXd nominal = model->parameters().nominal_values();
    const Scenario s = scenario(model, 40, 5);
    const MeasurementTable rad = read(*model, csv(*model, s.calibration, 1, ""));
    EXPECT_EQ(check_data_units(*model, nominal, rad), "") << name;
    const MeasurementTable deg = read(*model, csv(*model, s.calibration, 180 / kPi, ""));
    const std::string message = check_data_units(*model, nominal, deg);
    EXPECT_NE(message.find("looks like degrees"), std::string::npos) << name << ": " << message;
    EXPECT_NE(message.find("joint1_deg"), std::string::npos) << name << ": " << message;
    const MeasurementTable suffixed = read(*model, csv(*model, s.calibration, 180 / kPi, "_deg"));
    EXPECT_EQ(check_data_units(*model, nominal, suffixed), "") << name;
    EXPECT_LT((suffixed.data.actuators - s.calibration.actuators).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(DataUnits, EveryPresetsOwnDataPassesAndMetresAreCaught) {
  for (const auto& preset : list_presets()) {
    const auto model = make_preset(preset.name);
    const Scenario s = scenario(model, 30, 7);
    const MeasurementTable table = read(*model, csv(*model, s.calibration, 1, ""));
    EXPECT_EQ(check_data_units(*model, model->parameters().nominal_values(), table), "")
        << preset.name;
  }
  // Hexapod legs in metres.
  const auto hexapod = make_preset("cube-hexapod");
  const Scenario h = scenario(hexapod, 30, 7);
  const std::string legs = check_data_units(*hexapod, hexapod->parameters().nominal_values(),
                                            read(*hexapod, csv(*hexapod, h.calibration, 1e-3, "")));
  EXPECT_NE(legs.find("metres"), std::string::npos) << legs;
  EXPECT_NE(legs.find("leg1_m"), std::string::npos) << legs;
  // A laser tracker's readings in metres.
  const auto arm = make_preset("puma560");
  const Scenario a = scenario(arm, 30, 7);
  Measurements metres = a.calibration;
  metres.readings /= 1000;
  const std::string readings = check_data_units(
      *arm, arm->parameters().nominal_values(),
      read(*arm,
           measurements_to_csv(metres, arm->mechanism().actuator_names(), arm->reading_names())));
  EXPECT_NE(readings.find("tracker.x_m"), std::string::npos) << readings;
}

TEST(HomePoseCheck, NeverWarnsForASerialArm) {
  const auto model = make_preset("puma560");
  Measurements data = scenario(model, 30, 9).calibration;
  data.actuators.col(0).array() += 2.5;  // every pose far from home, turned about joint 1
  // Far indeed: where the former check warned (the closest pose > 100 mm from home).
  const VectorXd nominal = model->parameters().nominal_values();
  double nearest = 1e300;
  for (int r = 0; r < data.size(); ++r) {
    const auto fk = model->mechanism().forward_kinematics(
        nominal.head(model->mechanism().num_parameters()), data.actuators.row(r).transpose(),
        model->mechanism().home_pose());
    ASSERT_TRUE(fk.ok());
    nearest = std::min(nearest,
                       (fk.pose.translation - model->mechanism().home_pose().translation).norm());
  }
  EXPECT_GT(nearest, 100);
  const HomePoseCheck check =
      check_poses_near_home(*model, model->parameters().nominal_values(), data);
  EXPECT_FALSE(check.far) << check.warning;
  EXPECT_TRUE(check.warning.empty());
}

// Exact readings at the truth plus Gaussian noise of std `sigma` (Box-Muller, seed).
Measurements with_gaussian_noise(const Scenario& s, double sigma, std::uint64_t seed) {
  Measurements data = s.calibration;
  auto ws = s.model->make_workspace();
  VectorXd exact(s.model->num_readings());
  Random rng(seed);
  for (int r = 0; r < data.size(); ++r) {
    s.model->predict(s.truth, data.actuators.row(r).transpose(), exact, nullptr, ws);
    for (int i = 0; i < exact.size(); ++i) {
      const double u1 = 1 - rng.uniform01(), u2 = rng.uniform01();
      data.readings(r, i) =
          exact[i] + sigma * std::sqrt(-2 * std::log(u1)) * std::cos(2 * kPi * u2);
    }
  }
  return data;
}

struct Solved {
  CalibrationReport report;
  VectorXd values;
};

Solved calibrate(const Scenario& s, const Measurements& data, const std::string& loss = "") {
  const CalibrationProblem problem(s.model, data, s.nominal, s.free_indices);
  VectorXd x = problem.initial_free_parameters();
  const auto solver = SolverRegistry::global().create("lm");
  SolverOptions options;
  options.max_iterations = 200;
  if (!loss.empty()) options.loss = RobustLoss::parse(loss);
  const Summary summary = solver->solve(problem, x, options);
  EXPECT_EQ(summary.termination, TerminationType::kConverged) << summary.message;
  return {make_calibration_report(problem, x, summary, {},
                                  loss.empty() ? RobustLoss{} : RobustLoss::parse(loss)),
          problem.full_parameters(x)};
}

int flagged(const CalibrationReport& r) {
  int n = 0;
  for (bool o : r.outlier) n += o;
  return n;
}

// Issue 20 item 6: 1000 clean rows of a laser-tracked arm (3000 readings) flag about the
// expected tail (family-wise 5 %: over 8 data sets, 0 or 1 in each and a handful in all;
// measured: 1 in all 8), where the former robust 3-sigma rule flagged 60 (7.5 per data set);
// gross errors still stand out.
TEST(OutlierFlags, CleanGaussianDataFlagsTheExpectedTailAndGrossErrorsStandOut) {
  const auto model = make_preset("puma560");
  const double sigma = 0.02;
  int total = 0, former_total = 0;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    const Scenario s = scenario(model, 1000, seed, 1.0, 0.002);
    const Solved fit = calibrate(s, with_gaussian_noise(s, sigma, 100 + seed));
    const CalibrationReport& r = fit.report;
    EXPECT_NEAR(r.outlier_z, 4.3054, 1e-3);
    const int n = flagged(r);
    EXPECT_LE(n, 1) << "seed " << seed;
    total += n;
    // The former rule: 3 x 1.4826 x median |r|.
    const double former = 3 * r.outlier_threshold / r.outlier_z;
    for (int c = 0; c < r.residuals.rows(); ++c)
      former_total += (r.residuals.row(c).array().abs() > former).any();
    EXPECT_NEAR(r.uncertainty.sigma, sigma, 0.1 * sigma);
  }
  EXPECT_LE(total, 3);
  EXPECT_GE(former_total, 8 * 4);  // the old rule's ~8 per data set: the test can tell
  // Three gross errors of 10 sigma: flagged, and nothing else.
  const Scenario s = scenario(model, 1000, 21, 1.0, 0.002);
  Measurements data = with_gaussian_noise(s, sigma, 121);
  for (int row : {17, 400, 901}) data.readings(row, 1) += 10 * sigma;
  const CalibrationReport r = calibrate(s, data).report;
  EXPECT_EQ(flagged(r), 3);
  EXPECT_TRUE(r.outlier[17] && r.outlier[400] && r.outlier[901]);
}

// Under a robust loss the noise estimate is the std of the unweighted inlier residuals: on
// clean data it is the noise, where the psi-based figure (Cauchy shrinks even inliers) was
// smaller.
TEST(RobustNoiseEstimate, IsTheStdOfTheUnweightedInlierResiduals) {
  const auto model = make_preset("puma560");
  const double sigma = 0.02;
  const Scenario s = scenario(model, 300, 4, 1.0, 0.002);
  const Measurements data = with_gaussian_noise(s, sigma, 44);
  const CalibrationReport plain = calibrate(s, data).report;
  const CalibrationReport cauchy = calibrate(s, data, "cauchy:0.03").report;
  EXPECT_NEAR(cauchy.uncertainty.sigma, plain.uncertainty.sigma, 0.02 * plain.uncertainty.sigma);
  EXPECT_LT(cauchy.psi_sigma, 0.9 * cauchy.uncertainty.sigma);
  EXPECT_NEAR(cauchy.uncertainty.sigma, sigma, 0.1 * sigma);
  EXPECT_EQ(cauchy.inlier_readings, 900 - 3 * flagged(cauchy));
}

// The 3-D position error: before > registration only > after ~ noise; cross-validated error
// a little above the in-sample one; the predicted error of the measured point is computed.
TEST(PositionError, BeforeRegistrationAfterAndCrossValidation) {
  const auto model = make_preset("puma560");
  const double sigma = 0.01;
  const Scenario s = scenario(model, 120, 6, 1.0, 0.003);
  const Measurements data = with_gaussian_noise(s, sigma, 66);
  const Solved fit = calibrate(s, data);
  const CalibrationReport& r = fit.report;
  ASSERT_EQ(r.position_after.points, 120);
  EXPECT_GT(r.position_before.mean, 10 * r.position_after.mean);
  EXPECT_NEAR(r.position_after.rms, std::sqrt(3.0) * sigma, 0.3 * sigma);
  EXPECT_GT(r.predicted_point.points, 0);
  EXPECT_GT(r.predicted_point.mean_1sigma, 0);
  EXPECT_LT(r.predicted_point.mean_1sigma, sigma);

  const auto solver = SolverRegistry::global().create("lm");
  SolverOptions options;
  const std::vector<int> registration = registration_indices(*s.model, s.free_indices);
  std::vector<std::string> names;
  for (int i : registration) names.push_back(s.model->parameters()[i].name);
  for (const auto& n : names) EXPECT_EQ(n.rfind("tracker.", 0), 0u) << n;
  EXPECT_EQ(registration.size(), 9u);  // the tracker's frame and target
  const Fit baseline = fit_parameters(s.model, data, s.nominal, registration, *solver, options);
  ASSERT_TRUE(baseline.ok());
  const PositionErrorStats reg = summarize_position_errors(
      position_errors(*s.model, residual_matrix(s.model, data, baseline.values)));
  EXPECT_LT(reg.mean, r.position_before.mean);
  EXPECT_GT(reg.mean, 3 * r.position_after.mean);

  const CrossValidation cv =
      cross_validate(s.model, data, s.nominal, s.free_indices, 4, *solver, options);
  EXPECT_EQ(cv.failed_folds, 0);
  const PositionErrorStats held_out =
      summarize_position_errors(position_errors(*s.model, cv.residuals));
  EXPECT_EQ(held_out.points, 120);
  EXPECT_GT(held_out.rms, r.position_after.rms);
  EXPECT_LT(held_out.rms, 1.5 * r.position_after.rms);
  // Deterministic: the same folds give the same figures.
  const CrossValidation again =
      cross_validate(s.model, data, s.nominal, s.free_indices, 4, *solver, options);
  EXPECT_EQ((cv.residuals - again.residuals).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_THROW(cross_validate(s.model, data, s.nominal, s.free_indices, 1, *solver, options),
               std::invalid_argument);
}

TEST(PositionError, ALengthGaugeMeasuresNoPoint) {
  const auto model = make_preset("cube-hexapod");
  EXPECT_FALSE(measures_position(*model));
  EXPECT_TRUE(measures_position(*make_preset("ur5")));
}

}  // namespace
}  // namespace kincal
