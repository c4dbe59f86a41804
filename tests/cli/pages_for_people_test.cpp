// The pages for people (issue 21 items 4 and 5) from real command runs: no JSON object in
// any page's visible text, every page's sections and charts, --target's verdicts in the text,
// the JSON and the page, observability --html and calibrate --sensitivity, and what a single
// gauge cannot show. tests/cli/html_report_browser_test.sh opens the same pages in Chromium.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "kincal/cli/target_accuracy.hpp"

namespace kincal {
namespace {

using Json = nlohmann::ordered_json;
using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;

// What a person reads: the page without its style sheet and tags, entities decoded.
std::string visible_text(std::string html) {
  html = std::regex_replace(html, std::regex("<style>[^]*?</style>"), " ");
  html = std::regex_replace(html, std::regex("<[^>]*>"), " ");
  for (const auto& [entity, c] : std::vector<std::pair<std::string, std::string>>{
           {"&quot;", "\""}, {"&#39;", "'"}, {"&lt;", "<"}, {"&gt;", ">"}, {"&amp;", "&"}})
    for (std::size_t p = html.find(entity); p != std::string::npos; p = html.find(entity, p))
      html.replace(p, entity.size(), c);
  return html;
}

// "" when the text holds nothing that looks like JSON, else the first such excerpt.
std::string json_in(const std::string& text) {
  static const std::regex json(R"(\{\s*"|"\s*:\s*[\[{"0-9tfn-]|\[\s*\[|\[\s*\{|\{\s*\})");
  std::smatch m;
  if (!std::regex_search(text, m, json)) return "";
  const std::size_t at = static_cast<std::size_t>(m.position(0));
  return text.substr(at > 40 ? at - 40 : 0, 100);
}

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

std::vector<std::string> section_ids(const std::string& html) {
  std::vector<std::string> ids;
  static const std::regex section("<section id=\"([^\"]+)\">");
  for (std::sregex_iterator i(html.begin(), html.end(), section), end; i != end; ++i)
    ids.push_back((*i)[1]);
  return ids;
}

TEST(PagesForPeople, TheCheckerFindsJsonInText) {
  EXPECT_NE(json_in(visible_text("<td>{&quot;a&quot;: 1}</td>")), "");
  EXPECT_NE(json_in(visible_text("<td>[[1, 2], [3, 4]]</td>")), "");
  EXPECT_NE(json_in("x [{\"a\":1}]"), "");
  EXPECT_EQ(json_in(visible_text("<p>position 1.5 mm; \"quoted\" words: fine</p>")), "");
}

TEST(PagesForPeople, TargetIsALengthWithItsUnit) {
  TempDir dir("target");
  const std::string m = dir / "m.json";
  ASSERT_EQ(run_cli("model --out " + m).exit_code, 0);
  for (const std::string bad : {"0.1", "-1mm", "0mm", "fast", "0.5deg", "0.1mm,-1deg"}) {
    const auto r = run_cli("design --model " + m + " --poses 30 --out " + (dir / "t.csv") +
                           " --target '" + bad + "'");
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.err.find("--target '" + bad + "'"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "t.csv")) << bad;
  }
  TargetAccuracy target;
  target.position_mm = 0.1;
  EXPECT_EQ(judge_target(target, 0.05, NAN, "error", "").meets, std::optional<bool>(true));
  const TargetJudgement worse = judge_target(target, 0.35, NAN, "predicted error", "");
  EXPECT_EQ(worse.meets, std::optional<bool>(false));
  EXPECT_EQ(worse.verdict, "does not meet the 0.1 mm target: predicted error 0.35 mm");
  const TargetJudgement unknown = judge_target(target, NAN, NAN, "e", "no point measured");
  EXPECT_FALSE(unknown.meets.has_value());
  EXPECT_NE(unknown.verdict.find("no point measured"), std::string::npos);
  // With an angle: both must hold.
  target.has_orientation = true;
  target.orientation_rad = 1e-3;
  EXPECT_EQ(judge_target(target, 0.05, 2e-3, "e", "").meets, std::optional<bool>(false));
  EXPECT_EQ(judge_target(target, 0.05, 5e-4, "e", "").meets, std::optional<bool>(true));
}

// One campaign (the cube hexapod's single gauge, the paper's case 5) and every page of it.
class Pages : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir("pages");
    ASSERT_EQ(run_cli("model --out " + at("m.json")).exit_code, 0);
    ASSERT_EQ(run_cli("simulate --model " + at("m.json") + " --case 5 --seed 7 --write-data " +
                      at("d.csv"))
                  .exit_code,
              0);
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static std::string at(const std::string& file) { return (*dir_) / file; }
  static std::string page(const std::string& file) {
    const std::string html = read_text(at(file));
    EXPECT_EQ(json_in(visible_text(html)), "") << file << ": JSON in the page";
    return html;
  }
  static TempDir* dir_;
};
TempDir* Pages::dir_ = nullptr;

TEST_F(Pages, CalibrationReportHasTheAccuracyTheTargetAndTheSensitivity) {
  const auto r = run_cli("calibrate --model " + at("m.json") + " --data " + at("d.csv") +
                         " --out " + at("c.json") + " --json " + at("r.json") + " --html " +
                         at("r.html") + " --target 0.1mm --sensitivity");
  // The target is not met: do not load it, exit 3, every output written.
  ASSERT_EQ(r.exit_code, 3) << r.err;
  const std::string html = page("r.html");
  const std::vector<std::string> ids = section_ids(html);
  for (const char* id : {"verdicts", "residuals", "pose-accuracy", "sensitivity"})
    EXPECT_NE(std::find(ids.begin(), ids.end(), id), ids.end()) << id;
  // Residuals, histogram, corrections, correlation, singular values, pose error over the
  // workspace, sensitivity.
  EXPECT_EQ(count(html, "<svg"), 7u);
  EXPECT_NE(html.find("position, 95 % quantile, worst configuration (mm)"), std::string::npos);
  EXPECT_NE(html.find("does not meet the 0.1 mm target"), std::string::npos);
  // A single gauge: the report says what it cannot show, in the text, the JSON and the page.
  EXPECT_NE(r.out.find("note: the readings measure no point of the mechanism"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("target: does not meet the 0.1 mm target"), std::string::npos);
  EXPECT_NE(r.out.find("sensitivity to fixed parameters"), std::string::npos);
  const Json report = Json::parse(read_text(at("r.json")));
  EXPECT_EQ(report["pose_accuracy_shown"], false);
  EXPECT_NE(report["pose_accuracy_note"].get<std::string>().find("second placement"),
            std::string::npos);
  EXPECT_EQ(report["target"]["meets"], false);
  EXPECT_EQ(report["target"]["position_mm"], 0.1);
  EXPECT_EQ(report["predicted_pose_error"]["position_1sigma_mm_per_sample"]["calibrated"].size(),
            report["predicted_pose_error"]["workspace_samples"].get<std::size_t>());
  EXPECT_TRUE(report["sensitivity"].is_array());
  EXPECT_NE(html.find("do not confirm the pose accuracy"), std::string::npos);
  EXPECT_NE(html.find("a second placement"), std::string::npos);
  // A target met: said so.
  const auto easy =
      run_cli("calibrate --model " + at("m.json") + " --data " + at("d.csv") + " --target 100mm");
  EXPECT_NE(easy.out.find("target: meets the 100 mm target"), std::string::npos) << easy.out;
}

TEST_F(Pages, ValidationPagePlotsResidualsAndBeforeAfter) {
  ASSERT_EQ(run_cli("calibrate --model " + at("m.json") + " --data " + at("d.csv") + " --out " +
                    at("vc.json") + " --json " + at("vr.json"))
                .exit_code,
            0);
  // The calibration data as "held-out" data: the verdict does not matter here, the page does.
  const auto v = run_cli("validate --model " + at("vc.json") + " --data " + at("d.csv") +
                         " --report " + at("vr.json") + " --json " + at("v.json") + " --html " +
                         at("v.html") + " --target 0.1mm");
  ASSERT_NE(v.exit_code, 2) << v.err;
  const std::string html = page("v.html");
  EXPECT_EQ(section_ids(html),
            (std::vector<std::string>{"verdicts", "summary", "readings", "residuals", "position"}));
  // Residuals per configuration, and |residual| before and after: one point per configuration
  // and gauge in the first, two in the second.
  const Json j = Json::parse(read_text(at("v.json")));
  EXPECT_EQ(count(html, "<svg"), 2u);
  EXPECT_EQ(count(html, "<circle"), 3 * j["configurations"].get<std::size_t>());
  EXPECT_NE(html.find("Cannot say whether the pose meets the 0.1 mm target"), std::string::npos);
  EXPECT_NE(v.out.find("target: cannot say"), std::string::npos) << v.out;
  EXPECT_TRUE(j["target"]["meets"].is_null());
  EXPECT_TRUE(j["residuals"][0]["before"].is_object());
}

TEST_F(Pages, DesignPagePlotsTheChoiceAndTheExchange) {
  const auto g = run_cli("design --model " + at("m.json") +
                         " --poses 30 --candidates 300 --noise-std 0.0072mm --out " + at("t.csv") +
                         " --json " + at("g.json") + " --html " + at("g.html") + " --target 1mm");
  ASSERT_EQ(g.exit_code, 0) << g.err;
  const std::string html = page("g.html");
  EXPECT_EQ(section_ids(html),
            (std::vector<std::string>{"verdicts", "summary", "prediction", "configurations",
                                      "progress", "parameters", "search"}));
  const Json j = Json::parse(read_text(at("g.json")));
  // Pose error over the workspace (3 x 200 samples), the map, the criterion's progress.
  EXPECT_EQ(count(html, "<svg"), 3u);
  const std::size_t map_points =
      j["configuration_map"]["candidates"].size() + j["configuration_map"]["chosen"].size();
  EXPECT_EQ(j["configuration_map"]["chosen"].size(), 30u);
  EXPECT_EQ(j["exchange"]["pass_values"].size(), j["exchange"]["passes"].get<std::size_t>());
  EXPECT_EQ(count(html, "<circle"),
            3u * 200 + map_points + 1 + j["exchange"]["passes"].get<std::size_t>());
  // The last pass's value is the design's.
  EXPECT_DOUBLE_EQ(j["exchange"]["pass_values"].back().get<double>(),
                   j["exchange"]["value"].get<double>());
  EXPECT_TRUE(j["target"]["meets"].is_boolean());
  EXPECT_NE(g.out.find("target: "), std::string::npos);
}

TEST_F(Pages, ObservabilityHasAPage) {
  const auto o = run_cli("observability --model " + at("m.json") +
                         " --poses 40 --sensitivity --html " + at("o.html"));
  ASSERT_EQ(o.exit_code, 0) << o.err;
  const std::string html = page("o.html");
  EXPECT_EQ(section_ids(html),
            (std::vector<std::string>{"verdicts", "summary", "identifiability", "sensitivity"}));
  // Singular values (24 free parameters) and the sensitivity bars.
  EXPECT_EQ(count(html, "<svg"), 2u);
  EXPECT_EQ(count(html, "<circle"), 24u);
  // Outputs never overwrite inputs.
  const std::string model = read_text(at("m.json"));
  const auto clash =
      run_cli("observability --model " + at("m.json") + " --poses 40 --html " + at("m.json"));
  EXPECT_EQ(clash.exit_code, 2);
  EXPECT_EQ(read_text(at("m.json")), model);
}

TEST_F(Pages, ComparePageHoldsNoJson) {
  ASSERT_EQ(run_cli("calibrate --model " + at("m.json") + " --data " + at("d.csv") + " --out " +
                    at("cc.json"))
                .exit_code,
            0);
  ASSERT_EQ(run_cli("compare --truth " + at("d.truth.json") + " --model " + at("cc.json") +
                    " --html " + at("cmp.html"))
                .exit_code,
            0);
  EXPECT_EQ(count(page("cmp.html"), "<svg"), 2u);
}

// A point-measuring sensor shows the pose: no note.
TEST(PagesForPeople, APointTrackerNeedsNoNote) {
  TempDir dir("pages-point");
  ASSERT_EQ(run_cli("model --preset puma560 --out " + (dir / "p.json")).exit_code, 0);
  ASSERT_EQ(run_cli("simulate --model " + (dir / "p.json") + " --poses 40 --seed 3 --write-data " +
                    (dir / "p.csv"))
                .exit_code,
            0);
  const auto r =
      run_cli("calibrate --model " + (dir / "p.json") + " --data " + (dir / "p.csv") + " --json " +
              (dir / "r.json") + " --html " + (dir / "r.html") + " --folds 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("measure no point"), std::string::npos);
  // The measured position error: a table of five rows (before, registration only and
  // calibrated in-sample, both fits held out) and its chart, besides the residuals and their
  // histogram, the corrections in mm and in mrad, the correlation, the singular values and
  // the predicted pose error.
  const std::string html = read_text(dir / "r.html");
  EXPECT_EQ(json_in(visible_text(html)), "");
  EXPECT_EQ(count(html, "<svg"), 8u);
  EXPECT_NE(html.find("registration only, held out"), std::string::npos);
  EXPECT_EQ(html.find("do not confirm the pose accuracy"), std::string::npos);
  const Json report = Json::parse(read_text(dir / "r.json"));
  EXPECT_EQ(report["pose_accuracy_shown"], true);
  EXPECT_TRUE(report["pose_accuracy_note"].is_null());
}

}  // namespace
}  // namespace kincal
