// Missing readings (an empty field: the sensor did not measure that configuration) and
// reading weights: leaving a reading out must equal removing it, and a stated reading std
// must change nothing but the weighting.

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "kincal/framework/analysis/calibration_report.hpp"
#include "kincal/framework/calibration/measurement_file.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/hexapod.hpp"
#include "kincal/models/length_gauge.hpp"
#include "kincal/models/presets.hpp"
#include "newton_polish.hpp"

namespace kincal {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The cube hexapod with a second gauge at another placement, both free of nothing new.
std::shared_ptr<MeasurementModel> two_gauge_model() {
  const auto cube = make_cube_hexapod();
  auto second =
      std::make_shared<LengthGauge>("gauge2", Vector3d(250, -450, 480), Vector3d(150, -180, -20));
  auto model = std::make_shared<MeasurementModel>(
      cube->mechanism_ptr(),
      std::vector<std::shared_ptr<const Sensor>>{cube->sensors()[0], second});
  for (int i : cube->parameters().free_indices())
    model->parameters().set_free(cube->parameters()[i].name, true);
  return model;
}

Scenario noisy_scenario(std::shared_ptr<const MeasurementModel> model, int m) {
  ScenarioOptions options;
  options.num_configurations = m;
  options.noise_half_width.set(kincal::kMillimetre, 0.002);
  options.num_validation = 0;
  options.seed = 17;
  return make_scenario(model, options);
}

// The report at x, with the data file's line numbers (the header is line 1).
CalibrationReport report_at(const CalibrationProblem& problem, const VectorXd& x,
                            const Summary& summary) {
  std::vector<int> lines(problem.num_residual_blocks());
  for (int i = 0; i < problem.num_residual_blocks(); ++i) lines[i] = i + 2;
  return make_calibration_report(problem, x, summary, lines);
}

CalibrationReport solve(const CalibrationProblem& problem) {
  VectorXd x = problem.initial_free_parameters();
  const auto solver = SolverRegistry::global().create("lm");
  const Summary summary = solver->solve(problem, x, SolverOptions{});
  EXPECT_TRUE(summary.converged()) << summary.message;
  return report_at(problem, x, summary);
}

TEST(MissingReadings, AMissingGaugeReadingEqualsRemovingItsConfiguration) {
  const Scenario s = noisy_scenario(make_cube_hexapod(), 40);
  Measurements with_gaps = s.calibration;
  const std::vector<int> gaps = {3, 11, 12, 30};
  for (int r : gaps) with_gaps.readings(r, 0) = kNaN;
  const Measurements removed = drop_rows(s.calibration, gaps);

  const CalibrationProblem a(s.model, with_gaps, s.nominal, s.free_indices);
  const CalibrationProblem b(s.model, removed, s.nominal, s.free_indices);
  EXPECT_EQ(a.num_measured_residuals(), b.num_residuals());
  const VectorXd x0 = a.initial_free_parameters();
  VectorXd ra, rb;
  MatrixXd Ja, Jb;
  ASSERT_TRUE(a.evaluate(x0, &ra, &Ja));
  ASSERT_TRUE(b.evaluate(x0, &rb, &Jb));
  EXPECT_DOUBLE_EQ(ra.squaredNorm(), rb.squaredNorm());
  EXPECT_LT(((Ja.transpose() * Ja) - (Jb.transpose() * Jb)).norm(),
            1e-12 * (Jb.transpose() * Jb).norm());
  EXPECT_LT((Ja.transpose() * ra - Jb.transpose() * rb).norm(),
            1e-12 * (Jb.transpose() * rb).norm());

  const CalibrationReport ra_report = solve(a), rb_report = solve(b);
  // Same problem, so the same minimum; where lm stops in its flat end game (condition number
  // ~1e5) depends on rounding (the zero rows change the order of sums, and forward kinematics
  // starts from each solve's own previous poses), so the estimates agree to a tiny fraction
  // of their std, and what is computed at them (std, condition number) to about as much.
  EXPECT_LT((ra_report.estimate - rb_report.estimate)
                .cwiseQuotient(rb_report.uncertainty.std)
                .cwiseAbs()
                .maxCoeff(),
            1e-4);
  EXPECT_EQ(ra_report.uncertainty.degrees_of_freedom, rb_report.uncertainty.degrees_of_freedom);
  EXPECT_NEAR(ra_report.uncertainty.sigma, rb_report.uncertainty.sigma,
              1e-9 * rb_report.uncertainty.sigma);
  EXPECT_LT((ra_report.uncertainty.std - rb_report.uncertainty.std).cwiseAbs().maxCoeff(),
            1e-5 * rb_report.uncertainty.std.maxCoeff());
  EXPECT_EQ(ra_report.identifiability.num_residuals, rb_report.identifiability.num_residuals);
  EXPECT_NEAR(ra_report.identifiability.condition_number,
              rb_report.identifiability.condition_number,
              1e-5 * rb_report.identifiability.condition_number);
  EXPECT_EQ(ra_report.num_readings, 36);
  ASSERT_EQ(ra_report.readings_per_sensor.size(), 1u);
  EXPECT_EQ(ra_report.readings_per_sensor[0].second, 36);
  // The gaps show as missing, not as zero residuals.
  EXPECT_TRUE(std::isnan(ra_report.residuals(3, 0)));
  EXPECT_FALSE(ra_report.outlier[3]);
}

TEST(MissingReadings, AMissingReadingOfOneSensorLeavesTheOtherSensorsReadings) {
  const auto model = two_gauge_model();
  const Scenario s = noisy_scenario(model, 30);
  Measurements with_gaps = s.calibration;
  // gauge2 was moved away for the first ten configurations; gauge for the last five.
  for (int r = 0; r < 10; ++r) with_gaps.readings(r, 1) = kNaN;
  for (int r = 25; r < 30; ++r) with_gaps.readings(r, 0) = kNaN;
  const CalibrationProblem problem(model, with_gaps, s.nominal, s.free_indices);
  EXPECT_EQ(problem.num_measured_residuals(), 45);

  // The same least-squares problem written out reading by reading, without the gaps.
  const CalibrationProblem full(model, s.calibration, s.nominal, s.free_indices);
  const VectorXd x0 = problem.initial_free_parameters();
  VectorXd r, r_full;
  MatrixXd J, J_full;
  ASSERT_TRUE(problem.evaluate(x0, &r, &J));
  ASSERT_TRUE(full.evaluate(x0, &r_full, &J_full));
  std::vector<int> kept;
  for (int c = 0; c < 30; ++c)
    for (int i = 0; i < 2; ++i)
      if (!std::isnan(with_gaps.readings(c, i))) kept.push_back(2 * c + i);
  VectorXd r_kept(kept.size());
  MatrixXd J_kept(kept.size(), J.cols());
  for (std::size_t i = 0; i < kept.size(); ++i) {
    r_kept[i] = r_full[kept[i]];
    J_kept.row(i) = J_full.row(kept[i]);
  }
  EXPECT_DOUBLE_EQ(r.squaredNorm(), r_kept.squaredNorm());
  EXPECT_LT(((J.transpose() * J) - (J_kept.transpose() * J_kept)).norm(),
            1e-12 * (J_kept.transpose() * J_kept).norm());

  const CalibrationReport report = solve(problem);
  EXPECT_EQ(report.num_readings, 45);
  ASSERT_EQ(report.readings_per_sensor.size(), 2u);
  EXPECT_EQ(report.readings_per_sensor[0], (std::pair<std::string, int>("gauge", 25)));
  EXPECT_EQ(report.readings_per_sensor[1], (std::pair<std::string, int>("gauge2", 20)));
  EXPECT_EQ(report.uncertainty.degrees_of_freedom, 45 - 24);
  EXPECT_EQ(report.identifiability.num_residuals, 45);
}

TEST(MissingReadings, ARowWithoutReadingsNeedsNoForwardKinematics) {
  const Scenario s = noisy_scenario(make_cube_hexapod(), 30);
  Measurements data = s.calibration;
  data.actuators.row(4).setConstant(-50);  // unreachable: negative legs
  data.readings(4, 0) = kNaN;
  const CalibrationProblem problem(s.model, data, s.nominal, s.free_indices);
  VectorXd r;
  MatrixXd J;
  std::string why;
  EXPECT_TRUE(problem.evaluate(problem.initial_free_parameters(), &r, &J, &why)) << why;
  EXPECT_EQ(r[4], 0.0);
  EXPECT_TRUE(J.row(4).isZero());
  EXPECT_TRUE(find_unreachable_rows(*s.model, s.nominal, data).empty());
}

TEST(MissingReadings, EmptyFieldsReadAsMissingAndWriteBackEmpty) {
  const auto model = two_gauge_model();
  std::istringstream in(
      "leg1,leg2,leg3,leg4,leg5,leg6,gauge,gauge2\n"
      "354,354,354,354,354,382.1,600.5,\n"
      "355,354,354,354,354,382.1, ,610.25\n"
      "356,354,354,354,354,382.1,,\n");
  MeasurementTable table =
      parse_measurements(in, "D.csv", model->mechanism().actuator_names(), model->reading_names());
  check_sensor_readings(*model, table, "D.csv");
  ASSERT_EQ(table.data.size(), 3);
  EXPECT_EQ(table.data.readings(0, 0), 600.5);
  EXPECT_TRUE(std::isnan(table.data.readings(0, 1)));
  EXPECT_TRUE(std::isnan(table.data.readings(1, 0)));
  EXPECT_EQ(table.data.num_present(), 2);
  ASSERT_EQ(table.notices.size(), 1u);
  EXPECT_NE(table.notices[0].find("D.csv:4: no readings"), std::string::npos) << table.notices[0];

  const std::string csv =
      measurements_to_csv(table.data, model->mechanism().actuator_names(), model->reading_names());
  EXPECT_NE(csv.find(",600.5,\n"), std::string::npos) << csv;
  std::istringstream back(csv);
  const MeasurementTable again = parse_measurements(
      back, "E.csv", model->mechanism().actuator_names(), model->reading_names());
  EXPECT_TRUE(again.data.readings.cwiseEqual(table.data.readings).count() == 2);
  EXPECT_EQ(again.data.num_present(), 2);
}

TEST(MissingReadings, ReadersNameWhatIsWrong) {
  const auto model = two_gauge_model();
  auto error_of = [&](const std::string& text) {
    std::istringstream in(text);
    try {
      MeasurementTable t = parse_measurements(in, "D.csv", model->mechanism().actuator_names(),
                                              model->reading_names());
      check_sensor_readings(*model, t, "D.csv");
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const std::string header = "leg1,leg2,leg3,leg4,leg5,leg6,gauge,gauge2\n";
  EXPECT_EQ(error_of(header + "354,,354,354,354,382,600,601\n"),
            "D.csv:2: field 'leg2' is empty, expected a number");
  EXPECT_EQ(error_of(header + "354,354,354,354,354,382,,\n"),
            "D.csv: every reading is empty; expected measured readings");
}

// A two-reading sensor for the all-or-none rule: x and y of the platform origin.
class OriginXY final : public Sensor {
 public:
  std::string type() const override { return "origin-xy"; }
  const std::string& name() const override { return name_; }
  int num_readings() const override { return 2; }
  std::vector<std::string> reading_names() const override { return {"xy.x", "xy.y"}; }
  std::vector<std::string> reading_units() const override { return {"mm", "mm"}; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  void predict(const Eigen::Ref<const VectorXd>&, const Pose& pose, Eigen::Ref<VectorXd> reading,
               MatrixXd*, MatrixXd*) const override {
    reading = pose.translation.head<2>();
  }

 private:
  std::string name_ = "xy";
  std::vector<Parameter> parameters_;
};

TEST(MissingReadings, ASensorWithSomeButNotAllOfItsReadingsIsAnError) {
  // A multi-reading sensor is all or nothing: a tracker's target is seen or occluded.
  const auto cube = make_cube_hexapod();
  const MeasurementModel model(cube->mechanism_ptr(),
                               {cube->sensors()[0], std::make_shared<OriginXY>()});
  auto check = [&](const std::string& row) {
    std::istringstream in("leg1,leg2,leg3,leg4,leg5,leg6,gauge,xy.x,xy.y\n" + row + "\n");
    MeasurementTable t =
        parse_measurements(in, "D.csv", model.mechanism().actuator_names(), model.reading_names());
    try {
      check_sensor_readings(model, t, "D.csv");
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(check("354,354,354,354,354,382,600,1,2"), "(no error)");
  EXPECT_EQ(check("354,354,354,354,354,382,600,,"), "(no error)");
  EXPECT_EQ(check("354,354,354,354,354,382,,1,2"), "(no error)");
  EXPECT_EQ(check("354,354,354,354,354,382,600,1,"),
            "D.csv:2: sensor 'xy' has xy.x but not xy.y; expected all of its readings or none "
            "(leave every one empty when the sensor did not measure)");
}

TEST(ReadingStd, StatedNoiseRescalesResidualsButNotTheEstimateOrItsStd) {
  const Scenario s = noisy_scenario(make_cube_hexapod(), 40);
  auto weighted = std::make_shared<MeasurementModel>(*s.model);
  weighted->set_reading_std("gauge", 0.002 / std::sqrt(3.0));
  EXPECT_TRUE(weighted->weighted());
  const CalibrationProblem plain(s.model, s.calibration, s.nominal, s.free_indices);
  const CalibrationProblem whitened(weighted, s.calibration, s.nominal, s.free_indices);
  // Compared at the cost's minimum, resolved by Newton steps from each end point: lm stops
  // anywhere in the flat valley where the cost no longer changes by more than its rounding
  // (tests/newton_polish.hpp), and two scalings of one problem take it to different spots.
  auto polished = [](const CalibrationProblem& problem) {
    CalibrationReport report = solve(problem);
    double last_step = 0;
    const VectorXd x = testing::newton_polished(problem, report.estimate, &last_step);
    EXPECT_LT(last_step, 1e-7);
    return report_at(problem, x, report.summary);
  };
  const CalibrationReport a = polished(plain), b = polished(whitened);
  // (There they agree to ~2e-10 of the std; the end points, to ~2e-5.)
  EXPECT_LT((a.estimate - b.estimate).cwiseQuotient(a.uncertainty.std).cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_LT((a.uncertainty.std - b.uncertainty.std).cwiseAbs().maxCoeff(),
            1e-9 * a.uncertainty.std.maxCoeff());
  // sigma_hat is now the ratio of the scatter to the stated std: about 1 for uniform noise
  // of that std.
  EXPECT_NEAR(b.uncertainty.sigma, 1.0, 0.35);
  EXPECT_TRUE(b.weighted);
  // Residuals are reported in the reading's unit either way.
  EXPECT_LT((a.residuals - b.residuals).cwiseAbs().maxCoeff(), 1e-8 * a.residual_max.at("mm"));
}

}  // namespace
}  // namespace kincal

namespace kincal {
namespace {

TEST(ReadingStd, ASimulationOfMixedUnitsWeighsEachUnitByItsNoise) {
  ScenarioOptions options;
  options.noise_half_width.set(kincal::kMillimetre, 0.05);  // mm
  options.noise_half_width.set(kincal::kRadian, 2e-4);      // rad
  options.num_configurations = 40;
  options.num_validation = 0;
  options.seed = 3;
  const Scenario s = make_scenario(make_preset("ur5"), options);
  ASSERT_TRUE(s.model->weighted());
  const auto units = s.model->reading_units();
  for (std::size_t i = 0; i < units.size(); ++i)
    EXPECT_DOUBLE_EQ(s.model->reading_std()[i], (units[i] == "mm" ? 0.05 : 2e-4) / std::sqrt(3.0));
  const CalibrationReport report = solve(*s.make_problem());
  EXPECT_TRUE(report.weighted);
  EXPECT_NEAR(report.uncertainty.sigma, 1.0, 0.2);  // the scatter is as stated
  // A single-unit model is left unweighted: its figures stay those of plain least squares.
  options.noise_half_width.set(kincal::kRadian, 0);
  EXPECT_FALSE(make_scenario(make_preset("ur5"), options).model->weighted());
  EXPECT_FALSE(make_scenario(make_cube_hexapod(), options).model->weighted());
}

}  // namespace
}  // namespace kincal
