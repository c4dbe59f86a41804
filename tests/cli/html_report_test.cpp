// The report for people (cli/html_report, cli/svg_plot): well-formed markup, every user
// string escaped, no script and no network reference, the verdicts a person acts on, the
// optional sections, and calibrate --html through the real binary. The rendering in a real
// browser is tests/cli/html_report_browser_test.sh (ctest html_report_renders_in_chromium).

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <regex>
#include <vector>

#include "cli_runner.hpp"
#include "kincal/cli/html_pages.hpp"
#include "kincal/cli/html_report.hpp"
#include "kincal/cli/svg_plot.hpp"

namespace kincal {
namespace {

using cli::render_calibration_html;
using Json = nlohmann::ordered_json;
using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;

// A strict reader of the markup we write: every element closed in order (or self-closed,
// or a void HTML element), attribute values quoted, '&' only as an entity, no '<' in text.
// Returns "" when well-formed, else what is wrong and where.
std::string markup_problem(const std::string& s) {
  static const std::vector<std::string> kVoid = {"meta", "br", "hr", "img", "link", "input"};
  std::vector<std::string> open;
  std::size_t i = 0;
  if (s.rfind("<!DOCTYPE html>", 0) == 0) i = s.find('>') + 1;
  while (i < s.size()) {
    const char c = s[i];
    if (c == '&') {
      static const std::regex entity("^&(amp|lt|gt|quot|#[0-9]+);");
      if (!std::regex_search(s.substr(i, 10), entity)) return "bare & at " + std::to_string(i);
      ++i;
      continue;
    }
    if (c == '>') return "bare > at " + std::to_string(i);
    if (c != '<') {
      ++i;
      continue;
    }
    const std::size_t end = s.find('>', i);
    if (end == std::string::npos) return "unclosed tag at " + std::to_string(i);
    std::string tag = s.substr(i + 1, end - i - 1);
    if (tag.find('<') != std::string::npos) return "< inside a tag at " + std::to_string(i);
    i = end + 1;
    if (tag.rfind("?xml", 0) == 0 || tag.rfind("!--", 0) == 0) continue;
    if (tag[0] == '/') {
      const std::string name = tag.substr(1);
      if (open.empty() || open.back() != name)
        return "</" + name + "> closes <" + (open.empty() ? "" : open.back()) + ">";
      open.pop_back();
      continue;
    }
    const bool self_closed = tag.back() == '/';
    if (self_closed) tag.pop_back();
    const std::string name = tag.substr(0, tag.find_first_of(" \n"));
    // Attributes: name="value" with no quote inside the value.
    static const std::regex attrs(R"re(^[a-zA-Z0-9:-]+(\s+[a-zA-Z0-9:-]+="[^"]*")*\s*$)re");
    if (!std::regex_match(tag, attrs)) return "malformed tag <" + tag.substr(0, 80) + ">";
    if (!self_closed && std::find(kVoid.begin(), kVoid.end(), name) == kVoid.end())
      open.push_back(name);
  }
  return open.empty() ? "" : "<" + open.back() + "> never closed";
}

// A report in the shape of to_json(CalibrationReport), with names meant to break markup.
Json hostile_report() {
  const std::string evil = "<script>alert('x')</script>&\"leg";
  Json r;
  r["format"] = "kincal-calibration-report";
  r["model"] = "m<odel>.json";
  r["data"] = "d&ata.csv";
  r["solver"] = "lm";
  r["loss"] = "none";
  r["termination"] = "converged";
  r["message"] = "relative cost change < tolerance";
  r["iterations"] = 12;
  r["configurations"] = 4;
  r["readings"] = 4;
  r["residual_rms_by_unit"] = {{"mm", 0.01}};
  r["residual_max_by_unit"] = {{"mm", 0.05}};
  r["weighted"] = false;
  r["sigma_hat"] = 0.01;
  r["sigma_hat_unit"] = "mm";
  r["degrees_of_freedom"] = 2;
  r["parameters"] = Json::array(
      {{{"name", evil + "1"}, {"unit", "mm"}, {"nominal", 1.0}, {"estimate", 3.0}, {"std", 14.0}},
       {{"name", "leg2.x"},
        {"unit", "rad"},
        {"nominal", 0.1},
        {"estimate", 0.1002},
        {"std", 1e-3}}});
  r["correlation"] = Json::array({Json::array({1.0, 0.9999}), Json::array({0.9999, 1.0})});
  r["outlier_threshold"] = 0.03;
  r["reading_units"] = {{evil, "mm"}};
  r["reading_std"] = {{evil, nullptr}};
  r["residuals"] = Json::array();
  for (int c = 0; c < 4; ++c)
    r["residuals"].push_back(
        {{"line", c + 2}, {evil, c == 3 ? 0.05 : 0.001 * c}, {"outlier", c == 3}});
  r["identifiability"] = {
      {"parameters", 2},
      {"singular_values", {1.2, 3e-5}},
      {"numerical_rank", 2},
      {"numerical_rank_threshold", 1.2e-6},
      {"condition_number", 4e4},
      {"O1", 1e-3},
      {"combinations",
       Json::array({{{"singular_value", 3e-5},
                     {"kind", "weak"},
                     {"terms", Json::array({{{"name", evil + "1"}, {"coefficient", 0.9}}})}}})}};
  r["warnings"] = {"home <pose> & far"};
  // The library's verdict (framework/analysis/calibration_verdict.hpp), as calibrate writes it.
  r["verdict"] = {
      {"overall", "check"},
      {"findings",
       Json::array({{{"id", "solver"},
                     {"level", "good"},
                     {"text", "The solver converged (relative cost change < tolerance)."},
                     {"advice", ""}},
                    {{"id", "data"},
                     {"level", "warning"},
                     {"text", "home <pose> & far"},
                     {"advice", "Check the " + evil + " column."}}})}};
  return r;
}

TEST(SvgPlot, EscapesAndIsWellFormed) {
  EXPECT_EQ(cli::xml_escape("a<b>&\"c'"), "a&lt;b&gt;&amp;&quot;c&#39;");
  cli::SvgChart chart(300, 200, "t<i>tle & \"x\"");
  chart.set_x({0, 10, false, "x <mm>"});
  chart.set_y({1e-6, 10, true, "y & z"});
  chart.draw_axes();
  chart.point(5, 1e-3, 3, "a", "tip <b>");
  chart.rect(1, 1e-5, 2, 1, "bar");
  chart.polyline({{0, 1}, {10, 2}}, "curve");
  const std::string svg = chart.str();
  EXPECT_EQ(markup_problem(svg), "") << svg;
  EXPECT_EQ(svg.find("<i>"), std::string::npos);
  EXPECT_NE(svg.find("t&lt;i&gt;tle &amp; &quot;x&quot;"), std::string::npos);
}

TEST(SvgPlot, NiceTicksAreRoundAndCoverTheRange) {
  const auto t = cli::nice_ticks(-0.013, 0.027, 5);
  ASSERT_FALSE(t.empty());
  EXPECT_GE(t.front(), -0.013);
  EXPECT_LE(t.back(), 0.027);
  EXPECT_DOUBLE_EQ(t[1] - t[0], 0.01);
}

TEST(HtmlReport, HostileNamesAreEscapedAndThePageIsWellFormed) {
  const std::string html = render_calibration_html(hostile_report());
  EXPECT_EQ(markup_problem(html), "");
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_NE(html.find("&lt;script&gt;alert(&#39;x&#39;)&lt;/script&gt;&amp;&quot;leg"),
            std::string::npos);
  EXPECT_NE(html.find("m&lt;odel&gt;.json"), std::string::npos);
  // Self-contained: nothing loaded from anywhere.
  EXPECT_EQ(html.find("src="), std::string::npos);
  EXPECT_EQ(html.find("href=\"http"), std::string::npos);
  EXPECT_EQ(html.find("url("), std::string::npos);
  for (const char* id : {"verdicts", "summary", "residuals", "parameters", "correlation",
                         "identifiability", "outliers", "warnings"})
    EXPECT_NE(html.find(std::string("id=\"") + id + "\""), std::string::npos) << id;
  EXPECT_EQ(html.find("id=\"pose-accuracy\""), std::string::npos);
}

TEST(HtmlReport, VerdictsNameWhatToDo) {
  const auto verdicts = cli::calibration_verdicts(hostile_report());
  std::string all;
  for (const auto& v : verdicts) all += v.finding + " | " + v.action + "\n";
  EXPECT_NE(all.find("correlated at"), std::string::npos) << all;
  EXPECT_NE(all.find("--loss huber"), std::string::npos) << all;  // the outlier
  EXPECT_NE(all.find("Least determined (mm)"), std::string::npos) << all;
  EXPECT_NE(all.find("std 14 mm"), std::string::npos) << all;
  EXPECT_NE(all.find("--fix <script>"), std::string::npos) << all;  // raw here, escaped in HTML
  EXPECT_NE(all.find("ill-conditioned"), std::string::npos) << all;
  EXPECT_NE(all.find("home <pose> & far"), std::string::npos) << all;  // the report's warning
}

// The page says each finding of the library's verdict once, at its level, with its advice
// (the thresholds live in the library: the text and JSON reports carry the same findings).
TEST(HtmlReport, EachFindingOfTheVerdictIsSaidOnceAtItsLevel) {
  Json r = hostile_report();
  r["verdict"]["findings"].push_back(
      {{"id", "fit"},
       {"level", "do_not_load"},
       {"text", "The model leaves 100 % of the readings' spread unexplained."},
       {"advice", "Check that each row's readings belong to its configuration."}});
  std::string all;
  int problems = 0, fits = 0;
  for (const auto& v : cli::calibration_verdicts(r)) {
    all += v.finding + " | " + v.action + "\n";
    if (v.finding.find("100 % of the readings") != std::string::npos) {
      ++fits;
      EXPECT_EQ(v.level, cli::Verdict::Level::kProblem);
      EXPECT_NE(v.action.find("belong to its configuration"), std::string::npos);
    }
    if (v.level == cli::Verdict::Level::kProblem) ++problems;
  }
  EXPECT_EQ(fits, 1) << all;
  EXPECT_EQ(problems, 1) << all;
  // Without a verdict (a report of another program), no finding is invented.
  r.erase("verdict");
  for (const auto& v : cli::calibration_verdicts(r))
    EXPECT_EQ(v.finding.find("100 % of the readings"), std::string::npos);
}

TEST(HtmlReport, OptionalSectionsRenderWhenTheirFieldsExist) {
  Json r = hostile_report();
  r["predicted_pose_error"] = {
      {"computed", true},
      {"calibrated", {{"position_rms_mm", 8.5}, {"orientation_rms_rad", 1e-3}}},
      {"nominal", {{"position_rms_mm", 7.2}, {"orientation_rms_rad", 2e-3}}},
      {"expected_to_beat_nominal", false}};
  r["verdict"]["findings"].push_back(
      {{"id", "accuracy"},
       {"level", "warning"},
       {"text",
        "This calibration is not expected to beat the nominal model: predicted position "
        "error 8.5 mm RMS against 7.2 mm for the nominal model."},
       {"advice", "Measure configurations chosen by kincal design."}});
  r["parameters"][0]["prior_std"] = 2.0;
  r["parameters"][0]["data_share"] = 0.4;
  const std::string html = render_calibration_html(r);
  EXPECT_EQ(markup_problem(html), "");
  EXPECT_NE(html.find("id=\"pose-accuracy\""), std::string::npos);
  // The prediction as a table with its units, not the JSON keys.
  EXPECT_NE(html.find("position, RMS over the workspace (mm)"), std::string::npos) << html;
  EXPECT_EQ(html.find("position_rms_mm"), std::string::npos);
  EXPECT_NE(html.find("data share"), std::string::npos);
  EXPECT_NE(html.find("not expected to beat the nominal model"), std::string::npos);
  // Without the field, no section and no verdict about it.
  const std::string plain = render_calibration_html(hostile_report());
  EXPECT_EQ(plain.find("id=\"pose-accuracy\""), std::string::npos);
  EXPECT_EQ(plain.find("id=\"constraints\""), std::string::npos);
  EXPECT_EQ(plain.find("expected to beat"), std::string::npos);
}

// The summary names the formulation solved and, when it is not the one asked for, why
// (escaped: the note quotes the solver's message).
TEST(HtmlReport, TheSummaryNamesTheFormulationAndWhyItWasNotTheOneAskedFor) {
  Json r = hostile_report();
  r["formulation"] = "nested";
  r["formulation_note"] =
      "implicit formulation failed after 59 iterations (stalled <&>): solved nested from the "
      "same start";
  const std::string html = render_calibration_html(r);
  EXPECT_EQ(markup_problem(html), "");
  EXPECT_NE(html.find(", nested formulation</td>"), std::string::npos) << html;
  EXPECT_NE(html.find("<th class=\"name\">formulation</th><td class=\"name\">implicit "
                      "formulation failed after 59 iterations (stalled &lt;&amp;&gt;)"),
            std::string::npos)
      << html;
  r["formulation"] = "implicit";
  r["formulation_note"] = "";
  const std::string solved = render_calibration_html(r);
  EXPECT_NE(solved.find(", implicit formulation</td>"), std::string::npos);
  EXPECT_EQ(solved.find("<th class=\"name\">formulation</th>"), std::string::npos);
}

// Parameter-only constraints (a known distance between two sockets) get a table of their
// residuals against their stds, with hostile labels escaped.
TEST(HtmlReport, ConstraintsAreListedWithTheirResiduals) {
  Json r = hostile_report();
  r["constraints"] = Json::array({{{"type", "fixture-distance"},
                                   {"label", "|socket0 - socket1| <b>"},
                                   {"residual", 0.02},
                                   {"std", 0.05},
                                   {"unit", "mm"}}});
  const std::string html = render_calibration_html(r);
  EXPECT_EQ(markup_problem(html), "");
  EXPECT_NE(html.find("id=\"constraints\""), std::string::npos);
  EXPECT_NE(html.find("|socket0 - socket1| &lt;b&gt;"), std::string::npos) << html;
  EXPECT_NE(html.find("0.02 mm"), std::string::npos);
  EXPECT_NE(html.find("<td>0.4</td>"), std::string::npos);  // residual / std
}

// A point-measuring sensor: the measured 3-D position error (before, registration only,
// after, held out) is the verdict, instead of the workspace prediction's assumed "nominal".
TEST(HtmlReport, PositionErrorIsTheVerdictForAPointMeasuringSensor) {
  Json r = hostile_report();
  const auto stats = [](double mean) {
    return Json{{"points", 20}, {"mean", mean}, {"rms", mean * 1.1}, {"max", mean * 2}};
  };
  r["position_error_mm"] = {
      {"before", stats(2.5)}, {"registration_only", stats(0.6)}, {"after", stats(0.1)}};
  r["cross_validation"] = {{"folds", 5},
                           {"position_error_mm", stats(0.11)},
                           {"registration_only_position_error_mm", stats(0.62)}};
  r["predicted_point_error_mm"] = {{"points", 20}, {"mean_1sigma", 0.01}};
  r["predicted_pose_error"] = {
      {"computed", true},
      {"calibrated", {{"position_rms_mm", 8.5}, {"orientation_rms_rad", 1e-3}}},
      {"nominal", {{"position_rms_mm", 7.2}, {"orientation_rms_rad", 2e-3}}},
      {"expected_to_beat_nominal", false}};
  r["outlier_meaning"] = "a configuration is flagged when <z> ...";
  const std::string html = render_calibration_html(r);
  EXPECT_EQ(markup_problem(html), "");
  EXPECT_NE(html.find("id=\"position-error\""), std::string::npos);
  EXPECT_NE(html.find("2.5 mm before, 0.6 mm with registration only"), std::string::npos);
  EXPECT_NE(html.find("Held out (5-fold cross-validation): 0.11 mm"), std::string::npos);
  EXPECT_EQ(html.find("NOT expected to beat the nominal model"), std::string::npos);
  EXPECT_EQ(html.find("<z>"), std::string::npos);
  // Worse after than before: the figures are no longer "good"; the verdict on it is the
  // library's "accuracy" finding (tests/models/fit_verdict_test.cpp), rendered as given.
  r["position_error_mm"]["after"] = stats(3.0);
  for (const auto& v : cli::calibration_verdicts(r)) {
    if (v.finding.find("Mean 3-D position error") != std::string::npos) {
      EXPECT_EQ(v.level, cli::Verdict::Level::kNote) << v.finding;
    }
  }
  // No figure before (null): no verdict either way.
  r["position_error_mm"]["before"]["mean"] = nullptr;
  const std::string unknown = render_calibration_html(r);
  EXPECT_NE(unknown.find("could not both be computed"), std::string::npos);
  EXPECT_EQ(unknown.find("does not reduce the error"), std::string::npos);
}

// Degenerate reports (a failed solve: no residuals, no std, a zero Jacobian, nulls where
// numbers were expected) still give a well-formed page that says so.
TEST(HtmlReport, DegenerateReportsGiveAWellFormedPage) {
  Json r = hostile_report();
  r["termination"] = "failed";
  r["verdict"] = {
      {"overall", "do_not_load"},
      {"findings", Json::array({{{"id", "solver"},
                                 {"level", "do_not_load"},
                                 {"text", "The solver reached no solution (failed: <nan>)."},
                                 {"advice", "Check the data."}}})}};
  r["residuals"] = Json::array();
  r["sigma_hat"] = nullptr;
  r["correlation"] = Json::array();
  for (auto& p : r["parameters"]) p["std"] = nullptr;
  r["identifiability"]["singular_values"] = {0.0, 0.0};
  r["identifiability"]["condition_number"] = nullptr;
  const std::string html = render_calibration_html(r);
  EXPECT_EQ(markup_problem(html), "");
  EXPECT_NE(html.find("reached no solution (failed: &lt;nan&gt;)"), std::string::npos);
  EXPECT_NE(html.find("No residuals"), std::string::npos);
  EXPECT_NE(html.find("zero or not finite"), std::string::npos);
  EXPECT_EQ(markup_problem(render_calibration_html(Json::object())), "");
}

TEST(HtmlReport, CalibrateWritesItNextToTheJsonReport) {
  TempDir dir("html-report");
  const std::string m = dir / "nominal.json", d = dir / "data.csv";
  ASSERT_EQ(run_cli("model --out " + m).exit_code, 0);
  ASSERT_EQ(run_cli("simulate --model " + m + " --case 5 --seed 7 --write-data " + d).exit_code, 0);
  const auto result = run_cli("calibrate --model " + m + " --data " + d + " --json " +
                              (dir / "r.json") + " --html " + (dir / "r.html"));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::string html = read_text(dir / "r.html");
  EXPECT_EQ(markup_problem(html), "");
  EXPECT_NE(html.find("Verdicts"), std::string::npos);
  EXPECT_GE(std::count(html.begin(), html.end(), '\n'), 5);
  // Six charts: residuals, histogram, corrections (mm), correlation, singular values, the
  // predicted pose error over the workspace.
  std::size_t svgs = 0;
  for (std::size_t p = html.find("<svg"); p != std::string::npos; p = html.find("<svg", p + 1))
    ++svgs;
  EXPECT_EQ(svgs, 6u);
  // The same page from the JSON report: the HTML is a pure function of it.
  const Json report = Json::parse(read_text(dir / "r.json"));
  EXPECT_EQ(render_calibration_html(report), html);
  // --html - prints only the page.
  const auto to_stdout = run_cli("calibrate --model " + m + " --data " + d + " --html -");
  EXPECT_EQ(to_stdout.exit_code, 0) << to_stdout.err;
  EXPECT_EQ(to_stdout.out.rfind("<!DOCTYPE html>", 0), 0u);
}

// validate --html and design --html: pages from the commands' JSON, escaped, with verdicts.
TEST(HtmlPages, ValidationPageSaysWhetherTheResidualsAreAsPredicted) {
  Json v = {{"model", "<c>.json"},
            {"data", "held & out.csv"},
            {"configurations", 3},
            {"readings", 3},
            {"standardized_rms", 4.2},
            {"p_larger", 1e-9},
            {"parameter_uncertainty", true},
            {"verdict", "larger_than_predicted"},
            {"per_reading", Json::array({{{"name", "<g>"}, {"unit", "mm"}, {"rms", 0.04}}})},
            {"residuals", Json::array({{{"line", 2}, {"<g>", 0.04}}})}};
  std::string html = cli::render_validation_html(v);
  EXPECT_EQ(markup_problem(html), "");
  EXPECT_EQ(html.find("<c>"), std::string::npos);
  EXPECT_EQ(html.find("<g>"), std::string::npos);
  EXPECT_NE(html.find("&lt;c&gt;.json"), std::string::npos);
  EXPECT_NE(html.find("larger than predicted"), std::string::npos);
  v["verdict"] = "consistent";
  v["parameter_uncertainty"] = false;
  html = cli::render_validation_html(v);
  EXPECT_EQ(markup_problem(html), "");
  EXPECT_NE(html.find("what the calibration predicts"), std::string::npos);
  EXPECT_NE(html.find("taken as exact"), std::string::npos);
  // Untested, with the position error before and after.
  v["verdict"] = "not_tested";
  v["position_error_mm"] = {{"before", {{"points", 3}, {"mean", 2.5}, {"rms", 2.6}, {"max", 3.0}}},
                            {"after", {{"points", 3}, {"mean", 0.1}, {"rms", 0.11}, {"max", 0.2}}}};
  html = cli::render_validation_html(v);
  EXPECT_EQ(markup_problem(html), "");
  EXPECT_NE(html.find("consistency test is not made"), std::string::npos);
  EXPECT_NE(html.find("0.1 mm, against 2.5 mm before calibration"), std::string::npos);
  EXPECT_EQ(html.find("taken as exact"), std::string::npos);
}

TEST(HtmlPages, DesignPageComparesWithRandomAndNominal) {
  auto pose = [](double mm) {
    return Json{{"position_rms_mm", mm}, {"orientation_rms_rad", 1e-3}};
  };
  Json d = {{"model", "m<1>.json"},
            {"criterion", "D"},
            {"noise_std_assumed", true},
            {"predicted_pose_error",
             {{"designed", pose(0.5)}, {"random", pose(2.0)}, {"nominal", pose(7.0)}}},
            {"parameters", Json::array({{{"name", "leg1.base.z"}, {"designed_std", 0.1}}})}};
  std::string html = cli::render_design_html(d);
  EXPECT_EQ(markup_problem(html), "");
  EXPECT_EQ(html.find("m<1>"), std::string::npos);
  EXPECT_NE(html.find("(4 times)"), std::string::npos) << html;
  EXPECT_NE(html.find("expected to beat the nominal model"), std::string::npos);
  EXPECT_NE(html.find("noise was assumed"), std::string::npos);
  EXPECT_EQ(html.find("can do more than"), std::string::npos) << "no bound, no verdict on it";
  d["predicted_pose_error"]["designed"] = pose(9.0);
  html = cli::render_design_html(d);
  EXPECT_NE(html.find("Even this design is not expected to beat"), std::string::npos);
  // design --bound: a verdict in words, and the bound's figures in a sentence.
  d["count"] = 30;
  d["exchange"] = {{"passes", 2}, {"bound", {{"value", 1.5}, {"std_ratio", 1.0123}}}};
  html = cli::render_design_html(d);
  EXPECT_EQ(markup_problem(html), "");
  EXPECT_NE(html.find("No design of 30 from these candidates can do more than 1.23 % better"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("no design can pass 1.5"), std::string::npos) << html;
  EXPECT_EQ(html.find("&quot;std_ratio"), std::string::npos) << "a JSON dump in a cell";
}

TEST(HtmlPages, ValidateAndDesignWriteThePageOfTheirJson) {
  TempDir dir("html-pages");
  const std::string m = dir / "m.json", d = dir / "d.csv", c = dir / "c.json", r = dir / "r.json";
  ASSERT_EQ(run_cli("model --out " + m).exit_code, 0);
  ASSERT_EQ(run_cli("simulate --model " + m + " --case 5 --seed 7 --write-data " + d).exit_code, 0);
  ASSERT_EQ(
      run_cli("calibrate --model " + m + " --data " + d + " --out " + c + " --json " + r).exit_code,
      0);
  // The calibration data as "held-out" data: the verdict does not matter here, the page does.
  const std::string vj = dir / "v.json", vh = dir / "v.html";
  const auto v = run_cli("validate --model " + c + " --data " + d + " --report " + r + " --json " +
                         vj + " --html " + vh);
  ASSERT_NE(v.exit_code, 2) << v.err;
  EXPECT_EQ(read_text(vh), cli::render_validation_html(Json::parse(read_text(vj))));
  const std::string t = dir / "t.csv", dj = dir / "d.json", dh = dir / "d.html";
  const auto g =
      run_cli("design --model " + m + " --poses 30 --candidates 300 --noise-std 0.0072mm --out " +
              t + " --json " + dj + " --html " + dh);
  ASSERT_EQ(g.exit_code, 0) << g.err;
  EXPECT_EQ(read_text(dh), cli::render_design_html(Json::parse(read_text(dj))));
  EXPECT_EQ(markup_problem(read_text(dh)), "");
}

}  // namespace
}  // namespace kincal
