// The design loop without a script (issue 21 item 2): design -> simulate those configurations
// -> calibrate -> compare with the truth -> validate, on the default hexapod model, with
// explicit seeds; and compare's refusals.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"

namespace kincal {
namespace {

using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;
using Json = nlohmann::json;

double finite_number(const Json& j, const char* key) {
  EXPECT_TRUE(j.contains(key) && j[key].is_number()) << key << " in " << j.dump();
  const double v = j.contains(key) && j[key].is_number() ? j[key].get<double>() : NAN;
  EXPECT_TRUE(std::isfinite(v)) << key;
  return v;
}

TEST(CliWorkflowLoop, DesignSimulateCalibrateCompareValidate) {
  TempDir dir("workflow-loop");
  const std::string m = dir / "M.json", t = dir / "T.csv", d = dir / "D.csv",
                    truth = dir / "D.truth.json", c = dir / "C.json", r = dir / "R.json";
  ASSERT_EQ(run_cli("model --out " + m).exit_code, 0);
  // 1. Design 40 configurations for a gauge of 0.5 um noise std.
  const auto design =
      run_cli("design --model " + m +
              " --poses 40 --candidates 500 --noise-std 0.0005mm --seed 3 --out " + t);
  ASSERT_EQ(design.exit_code, 0) << design.err;
  // 2. Simulate the readings at exactly those configurations, from drawn errors.
  const auto sim = run_cli("simulate --model " + m + " --configs " + t +
                           " --noise-std 0.0005mm --seed 11 --validation 5 --write-data " + d);
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  ASSERT_TRUE(std::filesystem::exists(truth));
  EXPECT_NE(read_text(d).find("40 configurations of "), std::string::npos) << read_text(d);
  // The simulated data hold the template's configurations, in order.
  const auto first_row = [](const std::string& text) {
    std::size_t at = 0;
    int data_lines = 0;
    while (at < text.size()) {
      const std::size_t end = text.find('\n', at);
      const std::string line = text.substr(at, end - at);
      if (!line.empty() && line[0] != '#' && ++data_lines == 2)
        return line.substr(0, line.find(",", line.find(",") + 1));  // first two actuators
      at = end == std::string::npos ? text.size() : end + 1;
    }
    return std::string();
  };
  EXPECT_EQ(first_row(read_text(d)), first_row(read_text(t)));
  // 3. Calibrate.
  const auto cal =
      run_cli("calibrate --model " + m + " --data " + d + " --out " + c + " --json " + r);
  ASSERT_EQ(cal.exit_code, 0) << cal.err;
  // 4. Compare the result and the nominal model with the truth.
  const auto cmp = run_cli("compare --truth " + truth + " --model " + c + " --seed 2 --json -");
  ASSERT_EQ(cmp.exit_code, 0) << cmp.err;
  const Json after = Json::parse(cmp.out);
  EXPECT_EQ(after["format"], "kincal-compare");
  EXPECT_EQ(after["version"], 1);
  EXPECT_EQ(after["parameters"].size(), 24u);
  const double after_position = finite_number(after["pose_error"], "position_mean_mm");
  const double after_params = finite_number(after["parameter_error"]["mm"], "rms");
  finite_number(after["pose_error"], "orientation_mean_rad");
  EXPECT_EQ(after["pose_error"]["fk_failures"], 0);
  const auto nominal = run_cli("compare --truth " + truth + " --model " + m + " --seed 2 --json -");
  ASSERT_EQ(nominal.exit_code, 0) << nominal.err;
  const Json before = Json::parse(nominal.out);
  const double before_position = finite_number(before["pose_error"], "position_mean_mm");
  const double before_params = finite_number(before["parameter_error"]["mm"], "rms");
  // Small noise: the calibrated model is within a millimetre and far better than nominal
  // (the parameter errors were drawn within +-5 mm).
  EXPECT_LT(after_position, 1.0);
  EXPECT_LT(after_params, 1.0);
  EXPECT_GT(before_position, 2.0);
  EXPECT_LT(after_position * 5, before_position);
  EXPECT_LT(after_params * 3, before_params);
  // The configurations of the data file, text and page.
  const auto on_data = run_cli("compare --truth " + truth + " --model " + c + " --data " + d +
                               " --html " + dir / "compare.html");
  ASSERT_EQ(on_data.exit_code, 0) << on_data.err;
  EXPECT_NE(on_data.out.find("pose error over the 40 configurations of "), std::string::npos)
      << on_data.out;
  const std::string page = read_text(dir / "compare.html");
  EXPECT_NE(page.find("<svg"), std::string::npos);
  EXPECT_NE(page.find("Parameter errors against the truth"), std::string::npos);
  EXPECT_EQ(page.find("{\""), std::string::npos) << "no raw JSON in the page";
  // 5. Validate on held-out readings of the same truth at other configurations.
  const std::string held = dir / "H.csv";
  const auto held_sim =
      run_cli("simulate --model " + m + " --truth " + truth +
              " --poses 30 --noise-std 0.0005mm --seed 12 --validation 5 --write-data " + held);
  ASSERT_EQ(held_sim.exit_code, 0) << held_sim.err;
  EXPECT_NE(held_sim.out.find("true model given (--truth)"), std::string::npos) << held_sim.out;
  // The held-out data's truth is the one given.
  EXPECT_EQ(Json::parse(read_text(dir / "H.truth.json")), Json::parse(read_text(truth)));
  const auto val = run_cli("validate --model " + c + " --data " + held + " --report " + r);
  EXPECT_NE(val.exit_code, 2) << val.err;
  EXPECT_NE(val.out.find("consistent"), std::string::npos) << val.out;
}

TEST(CliWorkflowLoop, SimulateConfigsUsesTheTemplatesRowsAndTheGivenTruth) {
  TempDir dir("workflow-configs");
  const std::string m = dir / "M.json", t = dir / "T.csv";
  ASSERT_EQ(run_cli("model --out " + m).exit_code, 0);
  ASSERT_EQ(run_cli("design --model " + m + " --poses 30 --candidates 300 --noise-std 0.001mm " +
                    "--out " + t)
                .exit_code,
            0);
  // Noise-free readings from a given truth: the truth model itself (nominal) reproduces them
  // exactly, so calibrating from the nominal model recovers it.
  const auto sim = run_cli("simulate --model " + m + " --configs " + t + " --truth " + m +
                           " --seed 4 --validation 5 --write-data " + dir / "D.csv" + " --json " +
                           dir / "S.json");
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const Json s = Json::parse(read_text(dir / "S.json"));
  EXPECT_EQ(s["configs"], t);
  EXPECT_EQ(s["truth_model"], m);
  EXPECT_EQ(s["scenario"]["poses"], 30) << s["scenario"].dump();
  ASSERT_EQ(
      run_cli("calibrate --model " + m + " --data " + dir / "D.csv" + " --out " + dir / "C.json")
          .exit_code,
      0);
  const auto cmp = run_cli("compare --truth " + m + " --model " + dir / "C.json" + " --json -");
  ASSERT_EQ(cmp.exit_code, 0) << cmp.err;
  const Json j = Json::parse(cmp.out);
  EXPECT_LT(j["pose_error"]["position_max_mm"].get<double>(), 1e-6);
}

TEST(CliWorkflowLoop, BadInputIsOneLineAndExit2) {
  TempDir dir("workflow-bad");
  const std::string m = dir / "M.json", puma = dir / "P.json", t = dir / "T.csv";
  ASSERT_EQ(run_cli("model --out " + m).exit_code, 0);
  ASSERT_EQ(run_cli("model --preset puma560 --out " + puma).exit_code, 0);
  ASSERT_EQ(run_cli("design --model " + m + " --poses 30 --candidates 300 --noise-std 0.001mm " +
                    "--out " + t)
                .exit_code,
            0);
  const std::string out = dir / "out.json";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"compare --truth " + puma + " --model " + m + " --json " + out,
       "do not have the same parameters"},
      {"compare --model " + m + " --json " + out, "--truth FILE is required"},
      {"compare --truth " + m + " --model " + m + " --data " + t + " --poses 5 --json " + out,
       "without --poses"},
      {"compare --truth " + m + " --model " + m + " --json " + m, "--json"},
      {"simulate --model " + m + " --configs " + t + " --poses 5 --json " + out,
       "--configs gives the configurations"},
      {"simulate --model " + m + " --truth " + puma + " --json " + out,
       "do not have the same parameters"},
      {"simulate --model " + m + " --truth " + m + " --param-error 1mm --json " + out,
       "without --param-error"},
      {"simulate --model " + m + " --noise-std 0.001mm --noise-half-width 0.001 --json " + out,
       "--noise-std"},
  };
  for (const auto& [args, expected] : cases) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << args << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace kincal
