// The pages for people through the program (framework/report/ renders them; its own tests are
// tests/framework/report_pages_test.cpp): the SVG helper escapes and is well formed,
// calibrate, validate and design --html write well-formed pages. The rendering in a real
// browser is tests/cli/html_report_browser_test.sh (ctest html_report_renders_in_chromium).

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <regex>
#include <vector>

#include "cli_runner.hpp"
#include "kincal/framework/report/svg_plot.hpp"

namespace kincal {
namespace {

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

// validate --html and design --html: well-formed pages beside the JSON.
TEST(HtmlPages, ValidateAndDesignWriteTheirPages) {
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
  EXPECT_EQ(markup_problem(read_text(vh)), "");
  const std::string t = dir / "t.csv", dj = dir / "d.json", dh = dir / "d.html";
  const auto g =
      run_cli("design --model " + m + " --poses 30 --candidates 300 --noise-std 0.0072mm --out " +
              t + " --json " + dj + " --html " + dh);
  ASSERT_EQ(g.exit_code, 0) << g.err;
  EXPECT_EQ(markup_problem(read_text(dh)), "");
}

}  // namespace
}  // namespace kincal
