// Issue 24 item 4 through the real binary: the fit check flags a wrong model and a solve
// stopped short and passes a good run, in calibrate's text, JSON and HTML and in simulate's;
// --starts reports the distinct minima of a far start and continues with the lowest.

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"

namespace kincal {
namespace {

using kincal::testing::CliResult;
using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;
using Json = nlohmann::json;

constexpr const char* kFlag = "probably a local minimum or a model error";
// Calibrate's verdict on the same fit (framework/analysis/calibration_verdict.hpp): 40 gauge
// readings leave 3 degrees of freedom beyond the 24 free and 13 fixed directions, too few for
// the residuals' shape to clear the fit, so the stated noise decides.
constexpr const char* kShape = "their shape cannot tell the set-up";

// A model file, and data simulated from a truth whose fixed leg1.base.x is 3 mm off: no
// value of the free parameters explains them to the noise (a model error).
class FitCheckCli : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(run_cli("model --preset cube-hexapod --out " + dir_ / "m.json").exit_code, 0);
    Json truth = Json::parse(read_text(dir_ / "m.json"));
    truth["mechanism"]["legs"][0]["base"][0] =
        truth["mechanism"]["legs"][0]["base"][0].get<double>() + 3;
    std::ofstream(dir_ / "t.json") << truth.dump(1);
    const CliResult sim =
        run_cli("simulate --model " + dir_ / "m.json" + " --truth " + dir_ / "t.json" +
                " --poses 40 --noise-half-width 0.00125mm --seed 3 --write-data " + dir_ / "d.csv");
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
    simulate_text_ = sim.out;
  }
  TempDir dir_{"fit-check"};
  std::string simulate_text_;
};

TEST_F(FitCheckCli, CalibrateFlagsAWrongModelInTextJsonAndHtmlAndPassesTheRightOne) {
  const CliResult wrong =
      run_cli("calibrate --model " + dir_ / "m.json" + " --data " + dir_ / "d.csv" +
              " --noise-std 0.00072mm --json " + dir_ / "r.json" + " --html " + dir_ / "r.html");
  ASSERT_EQ(wrong.exit_code, 0) << wrong.err;
  EXPECT_NE(wrong.out.find(kShape), std::string::npos) << wrong.out;
  EXPECT_NE(wrong.out.find("verdict: check the warnings before loading it"), std::string::npos)
      << wrong.out;
  const Json report = Json::parse(read_text(dir_ / "r.json"));
  EXPECT_EQ(report["fit_check"]["verdict"], "too_large");
  EXPECT_EQ(report["fit_check"]["degrees_of_freedom"], 40 - 24);
  EXPECT_LT(report["fit_check"]["p_larger"].get<double>(), 1e-4);
  const std::string html = read_text(dir_ / "r.html");
  EXPECT_NE(html.find(kShape), std::string::npos);
  EXPECT_EQ(report["verdict"]["overall"], "check");  // never a plain success
  // Said once: sigma_hat (3.5 x reading_std here) gets no verdict of its own beside it.
  EXPECT_GT(report["sigma_hat"].get<double>(), 2);
  EXPECT_EQ(html.find("times the noise the model states"), std::string::npos);

  const CliResult right =
      run_cli("calibrate --model " + dir_ / "t.json" + " --data " + dir_ / "d.csv" +
              " --noise-std 0.00072mm --json " + dir_ / "r2.json" + " --html " + dir_ / "r2.html");
  ASSERT_EQ(right.exit_code, 0) << right.err;
  EXPECT_EQ(right.out.find("fit check"), std::string::npos) << right.out;
  const Json good = Json::parse(read_text(dir_ / "r2.json"));
  EXPECT_EQ(good["fit_check"]["verdict"], "consistent");
  EXPECT_GT(good["fit_check"]["p_larger"].get<double>(), 1e-4);
  const std::string good_html = read_text(dir_ / "r2.html");
  EXPECT_EQ(good_html.find(kShape), std::string::npos);
  EXPECT_EQ(good["verdict"]["overall"], "load");
  EXPECT_NE(good_html.find("The solver converged"), std::string::npos);
}

TEST_F(FitCheckCli, SimulateFlagsTheWrongModelAgainstTheSimulatedNoise) {
  EXPECT_NE(simulate_text_.find(kFlag), std::string::npos) << simulate_text_;
  const CliResult json =
      run_cli("simulate --model " + dir_ / "m.json" + " --truth " + dir_ / "t.json" +
              " --poses 40 --noise-half-width 0.00125mm --seed 3 --json -");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  EXPECT_EQ(Json::parse(json.out)["fit_check"]["verdict"], "too_large");
}

TEST_F(FitCheckCli, ASolveStoppedShortIsFlagged) {
  // Data with +-5 mm parameter errors, a solve stopped after 2 iterations.
  ASSERT_EQ(
      run_cli("simulate --model " + dir_ / "t.json" +
              " --poses 40 --noise-half-width 0.00125mm --seed 4 --write-data " + dir_ / "e.csv")
          .exit_code,
      0);
  const CliResult stopped = run_cli("calibrate --model " + dir_ / "t.json" + " --data " +
                                    dir_ / "e.csv" + " --noise-std 0.00072mm --max-iterations 2 " +
                                    "--json " + dir_ / "r.json" + " --html " + dir_ / "r.html");
  ASSERT_EQ(stopped.exit_code, 0) << stopped.err;
  const Json report = Json::parse(read_text(dir_ / "r.json"));
  EXPECT_EQ(report["termination"], "max_iterations");
  EXPECT_EQ(report["fit_check"]["verdict"], "too_large");
  EXPECT_NE(read_text(dir_ / "r.html").find("stopped at its iteration limit"), std::string::npos);
  EXPECT_EQ(report["verdict"]["overall"], "check");
}

TEST_F(FitCheckCli, WithoutAStatedNoiseItSaysWhatItCannotConclude) {
  ASSERT_EQ(run_cli("calibrate --model " + dir_ / "m.json" + " --data " + dir_ / "d.csv" +
                    " --json " + dir_ / "r.json")
                .exit_code,
            0);
  const Json fit = Json::parse(read_text(dir_ / "r.json"))["fit_check"];
  EXPECT_EQ(fit["verdict"], "not_tested");
  EXPECT_TRUE(fit["chi_square"].is_null());
  EXPECT_NE(fit["note"].get<std::string>().find("sigma_hat is estimated from these residuals"),
            std::string::npos)
      << fit["note"];
}

TEST(SimulateFitCheck, AGoodRunIsNotFlagged) {
  const CliResult text = run_cli("simulate --case 3 --seed 7 --validation 5");
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_EQ(text.out.find("fit check"), std::string::npos) << text.out;
  EXPECT_EQ(text.out.find("starts:"), std::string::npos) << text.out;  // one start, unchanged
  const CliResult json = run_cli("simulate --case 3 --seed 7 --validation 5 --json -");
  const Json j = Json::parse(json.out);
  EXPECT_EQ(j["fit_check"]["verdict"], "consistent");
  EXPECT_EQ(j["fit_check"]["degrees_of_freedom"], 40 - 24);
  EXPECT_EQ(j["starts"]["verdict"], "single_start");
}

// docs/benchmarks.md, "Local minima": case 2 from +-20 mm, seed 16. From nominal lm converges
// to a minimum that fits the noise; 8 starts find a lower one and continue with it.
TEST(Starts, SimulateReportsTheDistinctMinimaAndContinuesWithTheLowest) {
  const std::string run = "simulate --case 2 --param-error 20mm --seed 16 --validation 5";
  const Json one = Json::parse(run_cli(run + " --json -").out);
  const CliResult text = run_cli(run + " --starts 8");
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("distinct minima"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("start 0"), std::string::npos) << text.out;
  const Json eight = Json::parse(run_cli(run + " --starts 8 --json -").out);
  const Json& starts = eight["starts"];
  EXPECT_EQ(starts["count"], 8);
  EXPECT_EQ(starts["seed"], 16);
  EXPECT_EQ(starts["verdict"], "several_minima");
  EXPECT_NE(starts["best_start"], 0);
  ASSERT_GE(starts["minima"].size(), 2u);
  const double best = starts["minima"][0]["cost"].get<double>();
  EXPECT_LT(best, one["final_cost"].get<double>() * (1 - 1e-4));
  EXPECT_NEAR(eight["final_cost"].get<double>(), best, 1e-6 * best);
  // The single start's minimum is among those found, with start 0 in it.
  bool start_zero_found = false;
  for (const Json& m : starts["minima"])
    for (const Json& k : m["starts"]) start_zero_found = start_zero_found || k == 0;
  EXPECT_TRUE(start_zero_found);
  // Deterministic by seed.
  EXPECT_EQ(Json::parse(run_cli(run + " --starts 8 --json -").out)["starts"], starts);
}

TEST_F(FitCheckCli, CalibrateStartsAgreeOnGoodDataAndTheHtmlSaysSo) {
  const CliResult r = run_cli("calibrate --model " + dir_ / "t.json" + " --data " + dir_ / "d.csv" +
                              " --noise-std 0.00072mm --starts 4 --seed 5 --json " +
                              dir_ / "r.json" + " --html " + dir_ / "r.html");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("starts: 4"), std::string::npos) << r.out;
  const Json starts = Json::parse(read_text(dir_ / "r.json"))["starts"];
  EXPECT_EQ(starts["count"], 4);
  EXPECT_EQ(starts["seed"], 5);
  EXPECT_EQ(starts["verdict"], "one_minimum");
  EXPECT_TRUE(starts["spread_assumed"].get<bool>());  // the model file states no param_error
  EXPECT_NE(read_text(dir_ / "r.html").find("All 4 starts"), std::string::npos);
}

// The same data, tolerances and seed: calibrate --starts finds simulate's minima, and its
// page says that start 0 is not at the lowest.
TEST(Starts, CalibrateOnSimulatedDataFindsTheSameMinimaAsSimulate) {
  TempDir dir("starts");
  const std::string run = "simulate --case 2 --param-error 20mm --seed 16 --validation 5";
  const Json simulated = Json::parse(run_cli(run + " --starts 8 --json -").out)["starts"];
  ASSERT_EQ(run_cli(run + " --write-data " + dir / "d.csv").exit_code, 0);
  ASSERT_EQ(run_cli("model --preset cube-hexapod --out " + dir / "m.json").exit_code, 0);
  Json model = Json::parse(read_text(dir / "m.json"));
  model["param_error"] = {{"*", 20}};
  std::ofstream(dir / "m20.json") << model.dump(1);
  const CliResult r =
      run_cli("calibrate --model " + dir / "m20.json" + " --data " + dir / "d.csv" +
              " --starts 8 --seed 16 --json " + dir / "r.json" + " --html " + dir / "r.html");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json starts = Json::parse(read_text(dir / "r.json"))["starts"];
  EXPECT_FALSE(starts["spread_assumed"].get<bool>());
  EXPECT_EQ(starts["best_start"], simulated["best_start"]);
  ASSERT_EQ(starts["minima"].size(), simulated["minima"].size());
  for (std::size_t i = 0; i < starts["minima"].size(); ++i) {
    EXPECT_EQ(starts["minima"][i]["starts"], simulated["minima"][i]["starts"]);
    const double cost = simulated["minima"][i]["cost"].get<double>();
    EXPECT_NEAR(starts["minima"][i]["cost"].get<double>(), cost, 1e-9 * cost);
  }
  const std::string html = read_text(dir / "r.html");
  EXPECT_NE(html.find("distinct minima"), std::string::npos);
  EXPECT_NE(html.find("not from the model&#39;s values (start 0)"), std::string::npos);
}

TEST(Starts, BadCountsAreOneErrorLine) {
  for (const char* n : {"0", "-3", "10001"}) {
    const CliResult r = run_cli(std::string("simulate --case 3 --starts ") + n);
    EXPECT_EQ(r.exit_code, 2) << n;
    EXPECT_NE(r.err.find("--starts"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
}

}  // namespace
}  // namespace kincal
