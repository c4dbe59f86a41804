// The pages for people through the program (framework/report/ renders them; its own tests are
// tests/framework/report_pages_test.cpp and report_pages_more_test.cpp): the SVG helper
// escapes and is well formed, calibrate, validate and design --html write well-formed pages
// that say what their JSON says. The rendering in a real
// browser is tests/cli/html_report_browser_test.sh (ctest html_report_renders_in_chromium).

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <vector>

#include "cli_runner.hpp"
#include "kincal/framework/report/html_page.hpp"
#include "kincal/framework/report/svg_plot.hpp"
#include "markup_check.hpp"

namespace kincal {
namespace {

using Json = nlohmann::ordered_json;
using kincal::testing::markup_problem;
using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;

TEST(SvgPlot, EscapesAndIsWellFormed) {
  EXPECT_EQ(report::xml_escape("a<b>&\"c'"), "a&lt;b&gt;&amp;&quot;c&#39;");
  report::SvgChart chart(300, 200, "t<i>tle & \"x\"");
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
  const auto t = report::nice_ticks(-0.013, 0.027, 5);
  ASSERT_FALSE(t.empty());
  EXPECT_GE(t.front(), -0.013);
  EXPECT_LE(t.back(), 0.027);
  EXPECT_DOUBLE_EQ(t[1] - t[0], 0.01);
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
  // --html - prints only the page.
  const auto to_stdout = run_cli("calibrate --model " + m + " --data " + d + " --html -");
  EXPECT_EQ(to_stdout.exit_code, 0) << to_stdout.err;
  EXPECT_EQ(to_stdout.out.rfind("<!DOCTYPE html>", 0), 0u);
}

// validate --html and design --html: well-formed pages beside the JSON, saying what it says
// (the same result rendered twice: its verdict and figures, in words).
TEST(HtmlPages, ValidateAndDesignWriteThePageOfTheirResult) {
  TempDir dir("html-pages");
  const std::string m = dir / "m.json", d = dir / "d.csv", c = dir / "c.json", r = dir / "r.json";
  ASSERT_EQ(run_cli("model --out " + m).exit_code, 0);
  ASSERT_EQ(run_cli("simulate --model " + m + " --case 5 --seed 7 --write-data " + d).exit_code, 0);
  ASSERT_EQ(
      run_cli("calibrate --model " + m + " --data " + d + " --out " + c + " --json " + r).exit_code,
      0);
  // The calibration data as "held-out" data: whatever the verdict, the page says the JSON's.
  const std::string vj = dir / "v.json", vh = dir / "v.html";
  const auto v = run_cli("validate --model " + c + " --data " + d + " --report " + r + " --json " +
                         vj + " --html " + vh);
  ASSERT_NE(v.exit_code, 2) << v.err;
  const std::string validation = read_text(vh);
  EXPECT_EQ(markup_problem(validation), "");
  const Json vjson = Json::parse(read_text(vj));
  const std::string verdict = vjson["verdict"];
  const std::string said = verdict == "consistent" ? "are what the calibration predicts"
                           : verdict == "larger_than_predicted" ? "are larger than predicted"
                                                                : "are smaller than predicted";
  EXPECT_NE(validation.find("The held-out residuals " + said + ": standardized RMS " +
                            report::fmt(vjson["standardized_rms"].get<double>(), 3) +
                            " (1 = as predicted), P(larger) " +
                            report::fmt(vjson["p_larger"].get<double>(), 3)),
            std::string::npos)
      << verdict;
  EXPECT_NE(validation.find("<th class=\"name\">configurations</th><td class=\"name\">" +
                            std::to_string(vjson["configurations"].get<int>()) + " (" +
                            std::to_string(vjson["readings"].get<int>()) + " readings)</td>"),
            std::string::npos);

  // design --bound: the gain over a random design and the bound's figures, in sentences (no
  // JSON dump in a cell).
  const std::string t = dir / "t.csv", dj = dir / "d.json", dh = dir / "d.html";
  const auto g =
      run_cli("design --model " + m + " --poses 30 --candidates 300 --noise-std 0.0072mm --out " +
              t + " --json " + dj + " --html " + dh + " --bound");
  ASSERT_EQ(g.exit_code, 0) << g.err;
  const std::string design = read_text(dh);
  EXPECT_EQ(markup_problem(design), "");
  const Json djson = Json::parse(read_text(dj));
  const Json& pose = djson["predicted_pose_error"];
  const double designed = pose["designed"]["position_rms_mm"],
               random = pose["random"]["position_rms_mm"];
  EXPECT_NE(design.find("(" + report::fmt(random / designed, 3) + " times)"), std::string::npos);
  const Json& bound = djson["exchange"]["bound"];
  EXPECT_NE(design.find("No design of 30 from these candidates can do more than " +
                        report::fmt(100 * (bound["std_ratio"].get<double>() - 1), 3) + " % better"),
            std::string::npos);
  EXPECT_NE(design.find("no design can pass " + report::fmt(bound["value"].get<double>(), 6)),
            std::string::npos);
  EXPECT_EQ(design.find("std_ratio"), std::string::npos);
  EXPECT_EQ(design.find("&quot;"), std::string::npos);
}

}  // namespace
}  // namespace kincal
