// The report layer (framework/report/): pages rendered from typed results built in memory,
// no program and no JSON in between. Every name from the result is escaped, the findings
// are the verdict's and the page's at their levels, a degenerate result still gives a page.

#include <gtest/gtest.h>

#include <string>

#include "kincal/framework/report/calibration_page.hpp"
#include "kincal/framework/report/pages.hpp"

namespace kincal {
namespace {

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

}  // namespace
}  // namespace kincal
