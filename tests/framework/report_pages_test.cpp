// The report layer (framework/report/): pages rendered from typed results built in memory,
// no program and no JSON in between. Every name from the result is escaped, the findings
// are the verdict's and the page's at their levels, a degenerate result still gives a page;
// the validation and design pages of the workflows run on simulated data say what the run
// found. The calibration page of calibrate runs: report_pages_more_test.cpp.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/report/calibration_page.hpp"
#include "kincal/framework/report/html_page.hpp"
#include "kincal/framework/report/pages.hpp"
#include "kincal/framework/workflows/report_prediction.hpp"
#include "kincal/models/model_io.hpp"
#include "kincal/models/presets.hpp"
#include "kincal/models/serial_arm_presets.hpp"
#include "markup_check.hpp"

namespace kincal {
namespace {

using kincal::testing::markup_problem;

const std::string kHostile = "<script>alert('x')</script>&\"leg";

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

// Two parameters, one gauge reading, three configurations (one an outlier), the two
// estimates correlated at -1 and the identification severely ill-conditioned.
CalibrateResult hostile_result() {
  CalibrateResult result;
  result.solved = true;
  CalibrationReport& r = result.report;
  r.model_file = "m<odel>.json";
  r.data_file = "d&ata.csv";
  r.summary.solver = "lm";
  r.summary.termination = TerminationType::kConverged;
  r.summary.iterations = 7;
  r.summary.message = "ok <done>";
  r.names = {kHostile + "1", "leg2.base.x"};
  r.units = {"mm", "mm"};
  r.nominal = Eigen::Vector2d(1, 2);
  r.estimate = Eigen::Vector2d(1.5, 2.0001);
  r.uncertainty.sigma = 0.01;
  r.uncertainty.std = Eigen::Vector2d(5, 0.1);
  r.uncertainty.correlation = (Eigen::Matrix2d() << 1, -1, -1, 1).finished();
  r.num_configurations = 3;
  r.num_readings = 3;
  r.reading_names = {"gauge<1>"};
  r.reading_units = {"mm"};
  r.lines = {2, 3, 4};
  r.residuals = MatrixXd(3, 1);
  r.residuals << 0.01, -0.01, 0.5;
  r.outlier = {false, false, true};
  r.outlier_threshold = 0.1;
  r.residual_rms = {{"mm", 0.29}};
  r.residual_max = {{"mm", 0.5}};
  r.identifiability.num_parameters = 2;
  r.identifiability.numerical_rank = 2;
  r.identifiability.singular_values = Eigen::Vector2d(1, 1e-6);
  r.identifiability.numerical_threshold = 1e-7;
  r.identifiability.condition_number = 1e6;
  r.warnings = {"a warning <b>"};
  r.predicted_accuracy.why_not = "no <workspace>";
  result.verdict.findings.push_back(
      {"fit", Finding::Level::kDoNotLoad, "the fit <failed>", "do <this>"});
  return result;
}

TEST(ReportPages, ACalibrationPageFromATypedResultEscapesEveryName) {
  report::CalibrationPageExtras extras;
  extras.calibrated_model_file = "c<al>.json";
  extras.calibrated_model_sha256 = "ab";
  const std::string html = report::calibration_html(hostile_result(), extras);
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_NE(html.find("&lt;script&gt;alert(&#39;x&#39;)&lt;/script&gt;&amp;&quot;leg1"),
            std::string::npos);
  for (const char* text : {"m&lt;odel&gt;.json", "d&amp;ata.csv", "gauge&lt;1&gt;",
                           "a warning &lt;b&gt;", "c&lt;al&gt;.json (sha256 ab)",
                           "Not computed: no &lt;workspace&gt;.", "the fit &lt;failed&gt;"})
    EXPECT_NE(html.find(text), std::string::npos) << text;
  EXPECT_EQ(count(html, "<section"), count(html, "</section>"));
  EXPECT_EQ(count(html, "<svg"), count(html, "</svg>"));
  for (const char* id : {"verdicts", "summary", "residuals", "parameters", "correlation",
                         "identifiability", "outliers", "pose-accuracy", "warnings"})
    EXPECT_NE(html.find(std::string("id=\"") + id + "\""), std::string::npos) << id;
  EXPECT_EQ(html.find("id=\"position-error\""), std::string::npos);
}

TEST(ReportPages, TheFindingsAreTheVerdictsThenThePagesAtTheirLevels) {
  const std::vector<Finding> findings = report::calibration_page_findings(hostile_result());
  ASSERT_FALSE(findings.empty());
  EXPECT_EQ(findings[0].id, "fit");  // the verdict's first, as the text and JSON have them
  auto level_of = [&](const std::string& id) {
    for (const auto& f : findings)
      if (f.id == id) return static_cast<int>(f.level);
    return -1;
  };
  // Condition number 1e6 > kSeverelyIllConditioned; std 5 mm = 500 sigma_hat >
  // kWeakParameterAmplification; correlation -1 beyond kCorrelatedPair; line 4 flagged.
  EXPECT_EQ(level_of("conditioning"), static_cast<int>(Finding::Level::kWarning));
  EXPECT_EQ(level_of("least_determined"), static_cast<int>(Finding::Level::kWarning));
  EXPECT_EQ(level_of("correlation"), static_cast<int>(Finding::Level::kWarning));
  EXPECT_EQ(level_of("outliers"), static_cast<int>(Finding::Level::kWarning));
  EXPECT_EQ(level_of("starts"), -1);  // one start: nothing to say
  // A target not met is the caller's verdict finding, not repeated by the page.
  report::CalibrationPageExtras extras;
  TargetAccuracy target;
  target.position_mm = 0.1;
  extras.target = judge_target(target, 0.5, NAN, "error", "");
  for (const auto& f : report::calibration_page_findings(hostile_result(), extras))
    EXPECT_NE(f.id, "target");
  extras.target = judge_target(target, 0.05, NAN, "error", "");
  const auto met = report::calibration_page_findings(hostile_result(), extras);
  EXPECT_EQ(met.back().id, "target");
  EXPECT_EQ(met.back().level, Finding::Level::kGood);
}

// One correction 300 times the others' (the UR5's 33.7 mm reflector offset beside 0.1 mm
// joint corrections) gets a chart of its own, and no label is clipped: the left margin holds
// the longest name (29 characters) in the labels' 10 px monospace.
TEST(ReportPages, OneLargeCorrectionDoesNotSwampTheOthersAndNoLabelIsClipped) {
  CalibrateResult result;
  result.solved = true;
  CalibrationReport& r = result.report;
  const int n = 8;
  r.nominal = VectorXd::Zero(n);
  r.estimate = VectorXd(n);
  r.uncertainty.std = VectorXd::Constant(n, 0.02);
  for (int i = 0; i < n; ++i) {
    r.names.push_back(i == 0 ? "shoulder_lift_joint.origin.rz"
                             : "joint" + std::to_string(i) + ".x");
    r.units.push_back("mm");
    r.estimate[i] = 0.1 * (i % 3 - 1) + 0.05;
  }
  r.names[n - 1] = "tool.z";
  r.estimate[n - 1] = 33.7;
  const std::string html = report::calibration_html(result);
  EXPECT_EQ(count(html, ">Corrections (mm), the others<"), 1u) << html.substr(0, 2000);
  EXPECT_EQ(count(html, ">Corrections (mm), the large one on its own scale<"), 1u);
  // Every label's right end (text-anchor end) leaves room for its characters at 6 px each.
  for (std::size_t at = html.find("class=\"label\" x=\""); at != std::string::npos;
       at = html.find("class=\"label\" x=\"", at + 1)) {
    const double x = std::stod(html.substr(at + 17));
    const std::size_t open = html.find('>', at), close = html.find("</text>", open);
    const std::size_t chars = close - open - 1;
    EXPECT_GE(x, 6.0 * static_cast<double>(chars)) << html.substr(open, close - open);
  }
}

TEST(ReportPages, AnEmptyResultStillGivesAPage) {
  const std::string html = report::calibration_html(CalibrateResult());
  EXPECT_NE(html.find("No residuals"), std::string::npos);
  EXPECT_NE(html.find("No identifiability analysis"), std::string::npos);
  EXPECT_EQ(count(html, "<section"), count(html, "</section>"));
  EXPECT_NE(report::observability_html(ObservabilityResult()).find("No identifiability"),
            std::string::npos);
  EXPECT_NE(report::compare_html(CompareResult()).find("kincal compare"), std::string::npos);
}

TEST(ReportPages, AComparisonPageFromATypedResult) {
  CompareResult c;
  c.model_file = "a<b>.json";
  c.truth_file = "t.json";
  c.configurations = 2;
  c.pose.position = {0.1, 0.2};
  c.pose.orientation = {0.001, 0.002};
  c.pose.position_mean = 0.15;
  c.pose.position_max = 0.2;
  c.pose.orientation_mean = 0.0015;
  c.parameters.push_back({"p<1>", "mm", 1, 1.1, 0.1, true});
  const std::string html = report::compare_html(c);
  EXPECT_NE(html.find("a&lt;b&gt;.json"), std::string::npos);
  EXPECT_NE(html.find("p&lt;1&gt;"), std::string::npos);
  EXPECT_NE(html.find("off by 0.15 mm on average"), std::string::npos);
  EXPECT_EQ(count(html, "<svg"), 2u);
}

// The validation page from the validate workflow run in memory: the puma560's point tracker
// calibrated on 40 simulated configurations, validated on 20 others of the same machine.
class ValidationPageOfARun : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ScenarioOptions options;
    options.num_configurations = 40;
    options.noise_half_width = UnitValues{0.01, 0};
    options.seed = 3;
    options.num_validation = 20;
    const Scenario calibration = make_scenario(make_puma560(), options);
    CalibrateRequest request;
    request.model = calibration.model;
    request.measurements.data = calibration.calibration;
    const CalibrateResult result = calibrate(request);
    ASSERT_TRUE(result.solved);
    options.num_configurations = 20;
    options.seed = 4;
    options.truth = calibration.truth;
    held_out_ = new Measurements(make_scenario(make_puma560(), options).calibration);
    calibrated_ = model_with_values(*calibration.model, result.parameters);
    prediction_ =
        new ValidationPrediction(prediction_from_calibration(result.report, *calibrated_));
    nominal_ = new VectorXd(calibration.nominal);
  }
  static void TearDownTestSuite() {
    delete held_out_;
    delete prediction_;
    delete nominal_;
    calibrated_.reset();
  }
  static ValidateRequest request() {
    ValidateRequest r;
    r.model = calibrated_;
    r.measurements.data = *held_out_;
    r.prediction = *prediction_;
    r.model_file = "<c>.json";
    r.data_file = "held & out.csv";
    return r;
  }
  static Measurements* held_out_;
  static std::shared_ptr<MeasurementModel> calibrated_;
  static ValidationPrediction* prediction_;
  static VectorXd* nominal_;
};
Measurements* ValidationPageOfARun::held_out_ = nullptr;
std::shared_ptr<MeasurementModel> ValidationPageOfARun::calibrated_;
ValidationPrediction* ValidationPageOfARun::prediction_ = nullptr;
VectorXd* ValidationPageOfARun::nominal_ = nullptr;

TEST_F(ValidationPageOfARun, SaysWhetherTheResidualsAreAsPredicted) {
  const ValidateRequest as_predicted = request();
  const ValidateResult v = validate(as_predicted);
  ASSERT_EQ(v.validation.verdict, "consistent");
  ASSERT_TRUE(v.validation.parameter_uncertainty);
  std::string html = report::validation_html(as_predicted, v, "r.json");
  EXPECT_EQ(markup_problem(html), "");
  EXPECT_EQ(html.find("<c>"), std::string::npos);
  EXPECT_NE(html.find("&lt;c&gt;.json"), std::string::npos);
  EXPECT_NE(html.find("held &amp; out.csv"), std::string::npos);
  EXPECT_NE(html.find("<li class=\"good\"><span class=\"level\">OK</span>The held-out residuals "
                      "are what the calibration predicts: standardized RMS " +
                      report::fmt(v.validation.standardized_rms, 3)),
            std::string::npos);
  EXPECT_EQ(html.find("taken as exact"), std::string::npos);

  // Every reading 0.1 mm off (ten times the noise): larger than predicted, do not load.
  ValidateRequest shifted = request();
  shifted.measurements.data.readings.array() += 0.1;
  const ValidateResult larger = validate(shifted);
  ASSERT_EQ(larger.validation.verdict, "larger_than_predicted");
  html = report::validation_html(shifted, larger, "r.json");
  EXPECT_EQ(markup_problem(html), "");
  EXPECT_NE(html.find("<li class=\"problem\"><span class=\"level\">Problem</span>The held-out "
                      "residuals are larger than predicted"),
            std::string::npos);

  // The noise alone predicts them: the parameters are taken as exact.
  ValidateRequest noise_only = request();
  noise_only.prediction.parameters.clear();
  noise_only.prediction.covariance = MatrixXd();
  const ValidateResult exact = validate(noise_only);
  ASSERT_FALSE(exact.validation.parameter_uncertainty);
  html = report::validation_html(noise_only, exact, "");
  EXPECT_NE(html.find("the parameters are taken as exact"), std::string::npos);

  // Nothing predicts them: not tested; the 3-D position error against the values before.
  ValidateRequest untested = request();
  untested.prediction = ValidationPrediction();
  untested.before_values = *nominal_;
  untested.before_is = "the nominal model";
  const ValidateResult not_tested = validate(untested);
  ASSERT_EQ(not_tested.validation.verdict, "not_tested");
  ASSERT_TRUE(not_tested.position.computed);
  html = report::validation_html(untested, not_tested, "");
  EXPECT_EQ(markup_problem(html), "");
  EXPECT_NE(html.find("the consistency test is not made"), std::string::npos);
  EXPECT_NE(html.find(report::fmt(not_tested.position.after.mean) + " mm, against " +
                      report::fmt(not_tested.position.before.mean) + " mm before calibration."),
            std::string::npos);
  EXPECT_LT(not_tested.position.after.mean, not_tested.position.before.mean);
  EXPECT_EQ(html.find("taken as exact"), std::string::npos);
}

// The design page from the design workflow run in memory (the cube hexapod's gauge, 30 of 300
// candidates, with the bound): what the design gains over a random one and the nominal model,
// and how far any design of these candidates could go.
TEST(DesignPageOfARun, ComparesWithRandomAndNominalAndTheBound) {
  ExperimentDesignRequest request;
  request.model = make_cube_hexapod();
  request.noise_std = VectorXd::Constant(1, 0.0072);
  request.noise_source = "--noise-std";
  request.options.count = 30;
  request.options.num_random = 300;
  request.bound = true;
  request.model_file = "m<1>.json";
  ExperimentDesignResult result = design_experiment(request);
  const double designed = result.designed_pose.position_rms,
               random = result.random_pose.position_rms, nominal = result.nominal_pose.position_rms;
  ASSERT_LT(designed, random);
  ASSERT_LT(designed, nominal);
  ASSERT_TRUE(std::isfinite(result.bound.bound));
  std::string html = report::design_html(result, "t.csv");
  EXPECT_EQ(markup_problem(html), "");
  EXPECT_EQ(html.find("m<1>"), std::string::npos);
  EXPECT_NE(html.find("m&lt;1&gt;.json"), std::string::npos);
  EXPECT_NE(
      html.find("<li class=\"good\"><span class=\"level\">OK</span>Predicted position error "
                "over the workspace: " +
                report::fmt(designed, 3) + " mm RMS with this design, " + report::fmt(random, 3) +
                " mm with random configurations of the same "
                "count (" +
                report::fmt(random / designed, 3) + " times)."),
      std::string::npos);
  EXPECT_NE(html.find("Calibrating from it is expected to beat the nominal model (" +
                      report::fmt(nominal, 3) + " mm RMS)."),
            std::string::npos);
  EXPECT_NE(html.find("(each in its reading&#39;s unit; from --noise-std)"), std::string::npos);
  EXPECT_NE(html.find("No design of 30 from these candidates can do more than " +
                      report::fmt(100 * (result.std_ratio - 1), 3) + " % better than this one"),
            std::string::npos);
  EXPECT_NE(html.find("no design can pass " + report::fmt(result.bound.bound, 6)),
            std::string::npos);
  // Worse than the nominal model (changed in code: a run with these candidates beats it).
  result.designed_pose.position_rms = 2 * nominal;
  html = report::design_html(result, "t.csv");
  EXPECT_NE(html.find("<li class=\"problem\"><span class=\"level\">Problem</span>Even this design "
                      "is not expected to beat the nominal model"),
            std::string::npos);
}

}  // namespace
}  // namespace kincal
