// The calibration page (framework/report/calibration_page.hpp) rendered from what the calibrate
// workflow returned on simulated data in memory: the findings name what to do, each is said
// once at its level, the optional sections appear when the run has what they show (a prior,
// a constraint, a point-measuring sensor, a formulation that is not the one asked for), and a
// failed solve still gives a well-formed page. Where a condition is not reached by a run
// reliably (a correlation of +-1, a worse fit, a missing figure, a degenerate report), the
// run's typed result is changed in code.

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>

#include "kincal/framework/base/random.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/report/calibration_page.hpp"
#include "kincal/framework/report/html_page.hpp"
#include "kincal/models/fixture_distance.hpp"
#include "kincal/models/presets.hpp"
#include "kincal/models/serial_arm_presets.hpp"
#include "kincal/models/socket.hpp"
#include "kincal/models/urdf_arm.hpp"
#include "markup_check.hpp"

namespace kincal {
namespace {

using kincal::testing::markup_problem;
using report::esc;
using report::fmt;

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

// How the page opens a finding: its level's class and word, then its text (escaped).
std::string finding_item(const Finding& f) {
  static const char* kClass[] = {"good", "note", "warning", "problem"};
  static const char* kWord[] = {"OK", "Note", "Warning", "Problem"};
  const int level = static_cast<int>(f.level);
  return std::string("<li class=\"") + kClass[level] + "\"><span class=\"level\">" + kWord[level] +
         "</span>" + esc(f.text);
}

// The first finding about `id` (a copy: the findings are often a temporary).
std::optional<Finding> find(const std::vector<Finding>& findings, const std::string& id) {
  for (const auto& f : findings)
    if (f.id == id) return f;
  return std::nullopt;
}

// `configurations` simulated readings of `model` (its true parameters drawn around the
// nominal ones, U[-noise, noise] mm on each reading), reproducibly from `seed`.
Scenario simulated(std::shared_ptr<const MeasurementModel> model, int configurations, double noise,
                   std::uint64_t seed, const UnitValues& prior_std = {}) {
  ScenarioOptions options;
  options.num_configurations = configurations;
  options.noise_half_width = UnitValues{noise, 0};
  options.prior_std = prior_std;
  options.seed = seed;
  options.num_validation = 20;
  return make_scenario(std::move(model), options);
}

CalibrateRequest request_for(std::shared_ptr<const MeasurementModel> model,
                             const Measurements& data) {
  CalibrateRequest request;
  request.model = std::move(model);
  request.measurements.data = data;
  request.model_file = "m.json";
  request.data_file = "d.csv";
  return request;
}

CalibrateResult calibrate_data(std::shared_ptr<const MeasurementModel> model,
                               const Measurements& data, int folds = 0) {
  CalibrateRequest request = request_for(std::move(model), data);
  request.folds = folds;
  return calibrate(request);
}

// The cube hexapod's single length gauge, 30 configurations: ill-conditioned, its worst
// parameters hardly determined, not expected to beat the nominal model.
const CalibrateResult& cube_30() {
  static const CalibrateResult result = [] {
    const Scenario s = simulated(make_cube_hexapod(), 30, 0.0125, 7);
    return calibrate_data(s.model, s.calibration);
  }();
  return result;
}

TEST(CalibrationPageOfARun, TheFindingsNameWhatToDo) {
  const CalibrateResult& result = cube_30();
  ASSERT_TRUE(result.solved) << result.summary.message;
  const CalibrationReport& r = result.report;
  const std::vector<Finding> findings = report::calibration_page_findings(result);
  const std::string html = report::calibration_html(result);
  EXPECT_EQ(markup_problem(html), "");
  // The least determined parameter (the largest std in mm, hundreds of times sigma_hat): fix
  // it, by name.
  int worst = -1;
  for (int i = 0; i < static_cast<int>(r.names.size()); ++i)
    if (r.units[i] == "mm" && (worst < 0 || r.uncertainty.std[i] > r.uncertainty.std[worst]))
      worst = i;
  ASSERT_GE(worst, 0);
  ASSERT_GT(r.uncertainty.std[worst], report::kWeakParameterAmplification * r.uncertainty.sigma);
  std::optional<Finding> least = find(findings, "least_determined");
  ASSERT_TRUE(least);
  EXPECT_EQ(least->level, Finding::Level::kWarning);
  EXPECT_NE(least->text.find("Least determined (mm): " + r.names[worst] + " (std "),
            std::string::npos)
      << least->text;
  EXPECT_NE(html.find(esc("Fix it (--fix " + r.names[worst] + ")")), std::string::npos);
  std::optional<Finding> conditioning = find(findings, "conditioning");
  ASSERT_TRUE(conditioning);
  EXPECT_NE(conditioning->text.find("ill-conditioned"), std::string::npos);
  EXPECT_NE(html.find(finding_item(*conditioning)), std::string::npos);
  // Every advice is in the list of what to do next, escaped.
  for (const auto& f : findings) {
    if (f.advice.empty()) continue;
    EXPECT_NE(html.find("<li>" + esc(f.advice) + "</li>"), std::string::npos) << f.id;
  }

  // One reading off by 1 mm among 150 configurations: flagged, with the robust loss to try.
  const Scenario s = simulated(make_cube_hexapod(), 150, 0.0125, 7);
  Measurements data = s.calibration;
  data.readings(5, 0) += 1;
  const CalibrateResult off = calibrate_data(s.model, data);
  ASSERT_TRUE(off.solved) << off.summary.message;
  std::optional<Finding> outliers = find(report::calibration_page_findings(off), "outliers");
  ASSERT_TRUE(outliers);
  EXPECT_NE(outliers->text.find("line(s) 6"), std::string::npos) << outliers->text;
  EXPECT_NE(outliers->advice.find("re-run with --loss huber:"), std::string::npos);
  const std::string off_html = report::calibration_html(off);
  EXPECT_NE(off_html.find("<tr class=\"outlier\"><td>6</td>"), std::string::npos);

  // Two estimates correlated at -0.9995 (changed in code: a run's correlations near the
  // threshold move with the numerics): both named, and what to do.
  CalibrateResult correlated = result;
  correlated.report.uncertainty.correlation(0, 1) = -0.9995;
  correlated.report.uncertainty.correlation(1, 0) = -0.9995;
  std::optional<Finding> pair = find(report::calibration_page_findings(correlated), "correlation");
  ASSERT_TRUE(pair);
  EXPECT_NE(pair->text.find(r.names[1] + " and " + r.names[0] + " (-0.9995)"), std::string::npos)
      << pair->text;
  EXPECT_NE(report::calibration_html(correlated).find(finding_item(*pair)), std::string::npos);
}

// Each finding of the library's verdict is said once on the page, at its level; the page's
// own findings follow at theirs.
TEST(CalibrationPageOfARun, EachFindingIsSaidOnceAtItsLevel) {
  // Each row's readings from another row: the fit explains nothing, do not load it.
  const Scenario s = simulated(make_cube_hexapod(), 150, 0.0125, 7);
  Measurements shuffled = s.calibration;
  const int n = static_cast<int>(shuffled.readings.rows());
  for (int c = 0; c < n; ++c)
    shuffled.readings.row(c) = s.calibration.readings.row((7 * c + 3) % n);
  const CalibrateResult result = calibrate_data(s.model, shuffled);
  std::optional<Finding> fit = find(result.verdict.findings, "fit");
  ASSERT_TRUE(fit);
  EXPECT_EQ(fit->level, Finding::Level::kDoNotLoad);
  EXPECT_NE(fit->text.find("100 % of the readings' spread"), std::string::npos) << fit->text;
  EXPECT_NE(fit->advice.find("belong to its configuration"), std::string::npos);

  const std::vector<Finding> findings = report::calibration_page_findings(result);
  ASSERT_GE(findings.size(), result.verdict.findings.size());
  for (std::size_t i = 0; i < result.verdict.findings.size(); ++i)
    EXPECT_EQ(findings[i].text, result.verdict.findings[i].text) << i;
  const std::string html = report::calibration_html(result);
  EXPECT_EQ(markup_problem(html), "");
  int problems = 0;
  for (const auto& f : findings) {
    EXPECT_EQ(count(html, finding_item(f)), 1u) << f.id << ": " << f.text;
    EXPECT_EQ(count(html, esc(f.text)), 1u) << f.id;
    problems += f.level == Finding::Level::kDoNotLoad;
  }
  EXPECT_GE(problems, 1);
  EXPECT_EQ(count(html, "<li class=\"problem\">"), static_cast<std::size_t>(problems));
}

TEST(CalibrationPageOfARun, OptionalSectionsRenderWhenTheRunHasThem) {
  // Without a prior: the predicted pose accuracy as a table in words and units; the verdict
  // that it is not expected to beat the nominal model; no prior std; no constraint, no
  // measured point.
  const CalibrateResult& plain = cube_30();
  const std::string html = report::calibration_html(plain);
  EXPECT_NE(html.find("id=\"pose-accuracy\""), std::string::npos);
  EXPECT_NE(html.find("position, RMS over the workspace (mm)"), std::string::npos);
  EXPECT_EQ(html.find("position_rms_mm"), std::string::npos);
  std::optional<Finding> accuracy = find(plain.verdict.findings, "accuracy");
  ASSERT_TRUE(accuracy);
  EXPECT_NE(accuracy->text.find("not expected to beat the nominal model"), std::string::npos);
  EXPECT_NE(html.find(finding_item(*accuracy)), std::string::npos);
  const std::string name0 = "<td class=\"name\">" + esc(plain.report.names[0]) + "</td>";
  const std::size_t row0 = html.find(name0);
  ASSERT_NE(row0, std::string::npos);
  // Without a prior the data determine every parameter: data share 1, no prior std.
  EXPECT_NE(html.substr(row0, html.find("</tr>", row0) - row0)
                .find("<td>" + fmt(NAN, 3) + "</td><td>1</td>"),
            std::string::npos);
  for (const char* id : {"constraints", "position-error", "sensitivity"})
    EXPECT_EQ(html.find(std::string("id=\"") + id + "\""), std::string::npos) << id;

  // With a prior of 2 mm: its std and the data's share per parameter, and a prediction that
  // beats the nominal model.
  const Scenario s = simulated(make_cube_hexapod(), 30, 0.0125, 7, UnitValues{2, 0.01});
  const CalibrateResult prior = calibrate_data(s.model, s.calibration);
  ASSERT_TRUE(prior.solved);
  const ParameterUncertainty& u = prior.report.uncertainty;
  ASSERT_EQ(u.data_share.size(), static_cast<int>(prior.report.names.size()));
  const std::string with_prior = report::calibration_html(prior);
  EXPECT_EQ(markup_problem(with_prior), "");
  const std::size_t row = with_prior.find(name0);
  ASSERT_NE(row, std::string::npos);
  EXPECT_NE(with_prior.substr(row, with_prior.find("</tr>", row) - row)
                .find("<td>2</td><td>" + fmt(u.data_share[0], 3) + "</td>"),
            std::string::npos);
  EXPECT_LT(u.data_share[0], 1);
  std::optional<Finding> predicted =
      find(report::calibration_page_findings(prior), "predicted_accuracy");
  ASSERT_TRUE(predicted);
  EXPECT_EQ(predicted->level, Finding::Level::kGood);
  EXPECT_EQ(with_prior.find("not expected to beat"), std::string::npos);
}

// The summary names the formulation solved and, when it is not the one asked for, why.
TEST(CalibrationPageOfARun, TheSummaryNamesTheFormulationAndWhyItWasNotTheOneAskedFor) {
  const Scenario s = simulated(make_cube_hexapod(), 30, 0.0125, 7);
  CalibrateRequest request = request_for(s.model, s.calibration);
  request.formulation = Formulation::kImplicit;
  request.starts = 2;  // the starts solve the nested formulation
  CalibrateResult result = calibrate(request);
  ASSERT_TRUE(result.solved);
  ASSERT_FALSE(result.report.formulation_note.empty());
  std::string html = report::calibration_html(result);
  EXPECT_EQ(markup_problem(html), "");
  EXPECT_NE(html.find(", nested formulation</td>"), std::string::npos);
  EXPECT_NE(html.find("<th class=\"name\">formulation</th><td class=\"name\">implicit "
                      "formulation not used (--starts solves the nested one)</td>"),
            std::string::npos);
  // The note quotes a solver's message: escaped.
  result.report.formulation_note = "implicit formulation failed (stalled <&>)";
  html = report::calibration_html(result);
  EXPECT_EQ(markup_problem(html), "");
  EXPECT_NE(html.find("implicit formulation failed (stalled &lt;&amp;&gt;)"), std::string::npos);
  // Solved as asked: named, no note.
  request.starts = 1;
  const std::string solved = report::calibration_html(calibrate(request));
  EXPECT_NE(solved.find(", implicit formulation</td>"), std::string::npos);
  EXPECT_EQ(solved.find("<th class=\"name\">formulation</th>"), std::string::npos);
}

// The ur5-urdf arm put into two sockets 50.2 mm apart, calibrated with a fixture distance of
// 50 +- 0.05 mm: the constraint's residual against its std, in a table.
TEST(CalibrationPageOfARun, ConstraintsAreListedWithTheirResiduals) {
  const auto arm_model = make_ur5_urdf();
  const auto& arm = static_cast<const UrdfArm&>(arm_model->mechanism());
  const VectorXd arm_nominal = arm_model->parameters().nominal_values().head(arm.num_parameters());
  VectorXd home(arm.num_joints());
  arm.home_actuators(arm_nominal, home);
  const Pose home_pose = arm.forward_kinematics(arm_nominal, home, arm.home_pose()).pose;
  const Vector3d p0 = home_pose.translation + Vector3d(0, -25.1, 0);
  const Vector3d p1 = home_pose.translation + Vector3d(0, 25.1, 0);
  auto model = std::make_shared<MeasurementModel>(
      arm_model->mechanism_ptr(),
      std::vector<std::shared_ptr<const Sensor>>{
          std::make_shared<Socket>("socket0", p0 + Vector3d(3, -2, 4)),
          std::make_shared<Socket>("socket1", p1 + Vector3d(-2, 1, 3))});
  model->add_constraint(std::make_shared<FixtureDistance>("socket0", "socket1", 50, 0.05));
  model->parameters().set_free("socket*", true);
  model->set_reading_std("*", 0.01);  // the readings' noise, weighed against the constraint's
  const int per_socket = 12;
  Measurements data;
  data.actuators.resize(2 * per_socket, arm.num_joints());
  data.readings.setConstant(2 * per_socket, model->num_readings(), NAN);
  Random rng(24);
  for (int c = 0; c < 2 * per_socket; ++c) {
    Pose target = home_pose;
    target.translation = c < per_socket ? p0 : p1;
    target.rotation =
        exp_so3(Vector3d(rng.symmetric(0.4), rng.symmetric(0.4), rng.symmetric(0.4))) *
        home_pose.rotation;
    VectorXd q(arm.num_joints());
    ASSERT_TRUE(arm.inverse_kinematics(arm_nominal, target, q).ok());
    data.actuators.row(c) = q.transpose();
    for (int k = 0; k < 3; ++k)
      data.readings(c, (c < per_socket ? 0 : 3) + k) = rng.symmetric(0.01);
  }
  const CalibrateResult result = calibrate_data(model, data);
  ASSERT_TRUE(result.solved) << result.summary.message;
  ASSERT_EQ(result.report.constraints.size(), 1u);
  const auto& c = result.report.constraints[0];
  EXPECT_GT(std::abs(c.residual), 0.01);  // the data say 50.2, the constraint 50
  const std::string html = report::calibration_html(result);
  EXPECT_EQ(markup_problem(html), "");
  EXPECT_NE(html.find("id=\"constraints\""), std::string::npos);
  const std::string row = "<tr><td class=\"name\">" + esc(c.label) +
                          "</td><td class=\"name\">fixture-distance</td><td>" + fmt(c.residual, 4) +
                          " mm</td><td>0.05 mm</td><td>" + fmt(c.residual / 0.05, 3) + "</td></tr>";
  EXPECT_NE(html.find(row), std::string::npos) << row;
  EXPECT_NE(c.label.find("socket0"), std::string::npos);
}

// A point-measuring sensor (the puma560's tracker): the measured 3-D position error (before,
// registration only, calibrated, held out) is the verdict, not the workspace prediction.
TEST(CalibrationPageOfARun, PositionErrorIsTheVerdictForAPointMeasuringSensor) {
  const Scenario s = simulated(make_puma560(), 40, 0.01, 3);
  CalibrateResult result = calibrate_data(s.model, s.calibration, 2);
  ASSERT_TRUE(result.solved);
  const CalibrationReport& r = result.report;
  ASSERT_GT(r.position_after.points, 0);
  ASSERT_TRUE(r.registration.computed);
  const std::string html = report::calibration_html(result);
  EXPECT_EQ(markup_problem(html), "");
  EXPECT_NE(html.find("id=\"position-error\""), std::string::npos);
  EXPECT_NE(html.find(fmt(r.position_before.mean) + " mm before, "), std::string::npos);
  EXPECT_NE(
      html.find(fmt(r.registration.position.mean) + " mm with registration only (frames fitted), " +
                fmt(r.position_after.mean) + " mm calibrated."),
      std::string::npos);
  EXPECT_NE(html.find("Held out (2-fold cross-validation): " +
                      fmt(r.cross_validation.position.mean) + " mm calibrated"),
            std::string::npos);
  std::optional<Finding> position =
      find(report::calibration_page_findings(result), "position_error");
  ASSERT_TRUE(position);
  EXPECT_EQ(position->level, Finding::Level::kGood);
  EXPECT_NE(html.find(finding_item(*position)), std::string::npos);
  EXPECT_EQ(html.find("expected to beat the nominal model"), std::string::npos);
  EXPECT_FALSE(find(report::calibration_page_findings(result), "predicted_accuracy"));
  // Worse after than before (changed in code): the figures are no longer "good".
  CalibrateResult worse = result;
  worse.report.position_after.mean = 2 * r.position_before.mean;
  position = find(report::calibration_page_findings(worse), "position_error");
  ASSERT_TRUE(position);
  EXPECT_EQ(position->level, Finding::Level::kNote);
  // No figure before: no verdict either way.
  CalibrateResult unknown = result;
  unknown.report.position_before.mean = NAN;
  position = find(report::calibration_page_findings(unknown), "position_error");
  ASSERT_TRUE(position);
  EXPECT_EQ(position->level, Finding::Level::kNote);
  EXPECT_NE(position->text.find("could not both be computed"), std::string::npos);
}

// A failed solve whose report is degenerate (no residuals, no std, a zero Jacobian, NaN
// where numbers were expected), judged by the library's verdict: a well-formed page that
// says so.
TEST(CalibrationPageOfARun, ADegenerateReportGivesAWellFormedPage) {
  CalibrateResult result = cube_30();
  result.solved = false;
  CalibrationReport& r = result.report;
  r.summary.termination = TerminationType::kFailed;
  r.summary.message = "<nan> & more";
  const int n = static_cast<int>(r.names.size());
  r.residuals = MatrixXd(0, r.residuals.cols());
  r.outlier.clear();
  r.lines.clear();
  r.uncertainty.sigma = NAN;
  r.uncertainty.std = VectorXd::Constant(n, NAN);
  r.uncertainty.correlation = MatrixXd();
  r.identifiability.singular_values = VectorXd::Zero(n);
  r.identifiability.condition_number = NAN;
  r.identifiability.combinations.clear();
  result.verdict = judge_calibration(r);
  const std::string html = report::calibration_html(result);
  EXPECT_EQ(markup_problem(html), "");
  EXPECT_NE(html.find("<li class=\"problem\"><span class=\"level\">Problem</span>The solver "
                      "reached no solution (failed: &lt;nan&gt; &amp; more)."),
            std::string::npos);
  EXPECT_NE(html.find("No residuals"), std::string::npos);
  EXPECT_NE(html.find("No correlation matrix"), std::string::npos);
  EXPECT_NE(html.find("zero or not finite"), std::string::npos);
}

}  // namespace
}  // namespace kincal
