// What a calibration's verdict says of its fit, on a simulated UR5 (the ur5-urdf preset: the
// identifiable set free, a laser tracker): noise alone is "load it" whatever noise the model
// states; a frame frozen at a wrong value, an effect the model lacks and readings shuffled
// between rows are each named; an off-branch estimate is mapped back exactly; a calibration
// worse than its registration-only baseline is never a plain success.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "kincal/framework/analysis/calibration_report.hpp"
#include "kincal/framework/analysis/calibration_verdict.hpp"
#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/calibration/calibration_solve.hpp"
#include "kincal/framework/calibration/equivalent_solutions.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/urdf_arm.hpp"

#include <Eigen/Geometry>

namespace kincal {
namespace {

double gaussian(Random& rng) {
  const double u = 1 - rng.uniform01(), v = rng.uniform01();
  return std::sqrt(-2 * std::log(u)) * std::cos(2 * kPi * v);
}

struct Simulated {
  std::shared_ptr<MeasurementModel> model = make_ur5_urdf();
  VectorXd truth;
  Measurements data;
};

// 300 configurations over the joints' default box, readings of `truth` plus Gaussian noise
// of 0.05 mm; `effect` adds to each reading what the model does not have.
Simulated simulate(const std::function<void(const MeasurementModel&, VectorXd&)>& edit_truth,
                   const std::function<double(const VectorXd& q, int reading)>& effect = nullptr,
                   int m = 300) {
  Simulated s;
  s.truth = s.model->parameters().nominal_values();
  const auto& parameters = s.model->parameters();
  Random rng(11);
  for (int i : parameters.free_indices())
    s.truth[i] += parameters[i].unit == "rad" ? rng.symmetric(0.002) : rng.symmetric(0.5);
  edit_truth(*s.model, s.truth);
  const int k = s.model->num_readings();
  const Mechanism& arm = s.model->mechanism();
  s.data.actuators.resize(m, arm.num_actuators());
  s.data.readings.resize(m, k);
  auto ws = s.model->make_workspace();
  VectorXd home(arm.num_actuators());
  arm.home_actuators(s.truth.head(arm.num_parameters()), home);
  for (int c = 0; c < m; ++c) {
    VectorXd q = home;
    for (int a = 0; a < q.size(); ++a) q[a] += rng.symmetric(1.2);
    VectorXd y(k);
    EXPECT_TRUE(s.model->predict(s.truth, q, y, nullptr, ws).ok());
    for (int i = 0; i < k; ++i) y[i] += 0.05 * gaussian(rng) + (effect ? effect(q, i) : 0.0);
    s.data.actuators.row(c) = q.transpose();
    s.data.readings.row(c) = y.transpose();
  }
  return s;
}

CalibrationReport calibrate(const Simulated& s, VectorXd* x_out = nullptr) {
  const CalibrationProblem problem(s.model, s.data, s.model->parameters().nominal_values(),
                                   s.model->parameters().free_indices());
  VectorXd x = problem.initial_free_parameters();
  auto solver = SolverRegistry::global().create("lm");
  const CalibrationSolve solved =
      solve_calibration(*solver, problem, Prior{}, x, SolverOptions{}, Formulation::kNested);
  std::vector<int> lines(static_cast<std::size_t>(s.data.size()));
  for (int c = 0; c < s.data.size(); ++c) lines[static_cast<std::size_t>(c)] = c + 2;
  if (x_out) *x_out = x;
  return make_calibration_report(problem, x, solved.summary, lines);
}

bool has_finding(const CalibrationVerdict& v, const std::string& id, Finding::Level level,
                 const std::string& words = "") {
  for (const auto& f : v.findings)
    if (f.id == id && f.level == level && f.text.find(words) != std::string::npos) return true;
  return false;
}

std::string all_text(const CalibrationVerdict& v) { return to_text(v); }

TEST(FitVerdict, NoiseAloneIsLoadItWithTheNoiseEstimated) {
  const Simulated s = simulate([](const MeasurementModel&, VectorXd&) {});
  const CalibrationReport r = calibrate(s);
  ASSERT_TRUE(r.structure.tested) << r.structure.not_tested;
  EXPECT_FALSE(r.structure.neighbour_structured()) << r.structure.neighbour_fraction;
  EXPECT_FALSE(r.structure.fixed_structured()) << r.structure.fixed_fraction;
  EXPECT_LT(r.structure.unexplained_spread.at("mm"), 1e-3);
  const CalibrationVerdict v = judge_calibration(r);
  EXPECT_EQ(v.overall(), "load") << all_text(v);
  EXPECT_TRUE(has_finding(v, "fit", Finding::Level::kNote, "noise estimated")) << all_text(v);
}

TEST(FitVerdict, AFrameFrozenAtAWrongValueIsNamed) {
  // The tracker turned by 0.3 degrees about x, while the model's frame rotations about x and
  // y are fixed (nothing else in the preset's free set can turn the readings so).
  const Simulated s = simulate([](const MeasurementModel& model, VectorXd& truth) {
    truth[model.parameters().index_of("tracker.frame.rx")] += 0.3 * kRadiansPerDegree;
  });
  s.model->parameters().set_free("base.rx", false);
  s.model->parameters().set_free("base.ry", false);
  const CalibrationReport r = calibrate(s);
  EXPECT_TRUE(r.structure.fixed_structured()) << r.structure.fixed_fraction;
  const CalibrationVerdict v = judge_calibration(r);
  EXPECT_EQ(v.overall(), "check") << all_text(v);
  EXPECT_TRUE(has_finding(v, "fit", Finding::Level::kWarning, "fixed parameters")) << all_text(v);
  EXPECT_TRUE(r.structure.dominant_fixed.find(".rx") != std::string::npos)
      << r.structure.dominant_fixed;
}

TEST(FitVerdict, AnEffectTheModelLacksIsStructureNotNoise) {
  // A sag that grows with the arm's reach (a crude gravity deflection), 40 times the noise.
  const Simulated s =
      simulate([](const MeasurementModel&, VectorXd&) {},
               [](const VectorXd& q, int reading) {
                 return reading == 2 ? 2.0 * std::cos(q[1]) * std::cos(q[1] + q[2]) : 0.0;
               },
               800);
  const CalibrationReport r = calibrate(s);
  EXPECT_TRUE(r.structure.neighbour_structured() || r.structure.fixed_structured())
      << r.structure.neighbour_fraction << " " << r.structure.fixed_fraction;
  EXPECT_EQ(judge_calibration(r).overall(), "check") << all_text(judge_calibration(r));
}

TEST(FitVerdict, ReadingsShuffledBetweenRowsAreNotLoaded) {
  Simulated s = simulate([](const MeasurementModel&, VectorXd&) {});
  Random rng(5);
  for (int c = s.data.size() - 1; c > 0; --c) {
    const int other = std::min(c, static_cast<int>(rng.uniform01() * (c + 1)));
    s.data.readings.row(c).swap(s.data.readings.row(other));
  }
  const CalibrationReport r = calibrate(s);
  EXPECT_GT(r.structure.unexplained_spread.at("mm"), kUnexplainedSpread);
  const CalibrationVerdict v = judge_calibration(r);
  EXPECT_EQ(v.overall(), "do_not_load") << all_text(v);
  EXPECT_TRUE(has_finding(v, "fit", Finding::Level::kDoNotLoad, "unexplained")) << all_text(v);
}

TEST(FitVerdict, StatedNoiseAboveTheDatasheetWithoutStructureIsANote) {
  // The model states a tenth of the real noise: sigma_hat is 10, the residuals unstructured.
  Simulated s = simulate([](const MeasurementModel&, VectorXd&) {});
  s.model->set_reading_std("*", 0.01);
  const CalibrationReport r = calibrate(s);
  ASSERT_TRUE(r.weighted);
  EXPECT_TRUE(r.fit_check.too_large());
  const CalibrationVerdict v = judge_calibration(r);
  EXPECT_EQ(v.overall(), "load") << all_text(v);
  EXPECT_TRUE(has_finding(v, "fit", Finding::Level::kNote, "times the stated noise"))
      << all_text(v);
}

TEST(FitVerdict, WorseThanTheRegistrationBaselineIsNotLoaded) {
  const Simulated s = simulate([](const MeasurementModel&, VectorXd&) {});
  CalibrationReport r = calibrate(s);
  r.registration.computed = true;
  r.registration.position = r.position_after;
  r.registration.position.rms = r.position_after.rms / 2;
  const CalibrationVerdict v = judge_calibration(r);
  EXPECT_EQ(v.overall(), "do_not_load") << all_text(v);
  EXPECT_TRUE(has_finding(v, "baseline", Finding::Level::kDoNotLoad, "registration only"));
  // Held out too.
  CalibrationReport h = calibrate(s);
  h.cross_validation.folds = 5;
  h.cross_validation.position = h.position_after;
  h.cross_validation.registration_position = h.position_after;
  h.cross_validation.registration_position.rms = h.position_after.rms / 2;
  EXPECT_TRUE(
      has_finding(judge_calibration(h), "baseline", Finding::Level::kDoNotLoad, "Held out"));
}

TEST(FitVerdict, AnOffBranchEstimateIsMappedBackExactly) {
  const Simulated s = simulate([](const MeasurementModel&, VectorXd&) {});
  VectorXd x;
  const CalibrationReport r = calibrate(s, &x);
  const CalibrationProblem problem(s.model, s.data, s.model->parameters().nominal_values(),
                                   s.model->parameters().free_indices());
  // The estimate's twin with the shoulder's zero turned by pi, the elbow's origin turned about
  // the parallel axes (its translation reversed: Rz(pi) Tx(-a) = Tx(a) Rz(pi)) and the
  // elbow's zero turned back: the flip a wandering solver ends in on real data, every pose
  // the same (checked below by the predictions).
  const auto& arm = static_cast<const UrdfArm&>(s.model->mechanism());
  VectorXd full = problem.full_parameters(x);
  const int lift = s.model->parameters().index_of("shoulder_lift_joint.offset");
  const int elbow_origin = s.model->parameters().index_of("elbow_joint.origin.x");
  full[lift] += kPi;
  {
    const UrdfArmJoint& lift_joint = arm.nominal_geometry().joints[1];
    const Pose C = frame_from_parameters(arm.nominal_geometry().joints[2].origin);
    const Pose E = frame_from_parameters(full.segment<6>(elbow_origin));
    Pose turn;
    turn.rotation = Eigen::AngleAxisd(kPi, lift_joint.axis).toRotationMatrix();
    full.segment<6>(elbow_origin) =
        frame_parameters(compose(inverse(C), compose(turn, compose(C, compose(E, turn)))));
    full[s.model->parameters().index_of("elbow_joint.offset")] += kPi;
  }
  // What is fixed keeps its exact value (the frame conversions round it).
  const VectorXd estimate = problem.full_parameters(x);
  std::vector<bool> is_free(static_cast<std::size_t>(full.size()), false);
  for (int i : problem.free_indices()) is_free[static_cast<std::size_t>(i)] = true;
  for (int i = 0; i < full.size(); ++i)
    if (!is_free[static_cast<std::size_t>(i)]) full[i] = estimate[i];
  const VectorXd x_twin = problem.free_parameters(full);
  ASSERT_TRUE(problem.full_parameters(x_twin) == full) << "the twin moves only free parameters";
  ASSERT_LT((residual_matrix(problem, x_twin) - residual_matrix(problem, x)).cwiseAbs().maxCoeff(),
            1e-8)
      << "the test's twin predicts what the estimate does";
  // Reported as it is, the twin is off branch and far beyond the tolerances.
  CalibrationReport off = make_calibration_report(problem, x_twin, r.summary, {});
  EXPECT_FALSE(off.off_branch.empty());
  EXPECT_EQ(judge_calibration(off).overall(), "do_not_load");
  // Mapped, it is the estimate again, every prediction unchanged.
  const NominalBranch branch = map_to_nominal_branch(problem, x_twin);
  ASSERT_FALSE(branch.mapped.empty()) << branch.rejected;
  EXPECT_LE(branch.prediction_change, 1e-6);
  for (int i = 0; i < x.size(); ++i) EXPECT_NEAR(wrap_angle(branch.x[i] - x[i]), 0, 1e-6) << i;
}

}  // namespace
}  // namespace kincal
