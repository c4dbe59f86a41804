// Prior knowledge on the command line (--prior-std on calibrate, observability, simulate) and
// `kincal validate` on held-out data, through the real binary.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_runner.hpp"

namespace kincal {
namespace {

using kincal::testing::count_lines;
using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;
using Json = nlohmann::json;

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

constexpr double kNoise = 0.0125;  // the paper's cases 4 and 5

class CliPrior : public ::testing::Test {
 protected:
  // The cube hexapod stating its gauge's noise, 100 simulated configurations (case 4/5 noise)
  // split into 60 for calibration and 40 held out, all from the same true geometry.
  static void SetUpTestSuite() {
    dir_ = new TempDir("prior");
    ASSERT_EQ(run_cli("model --out " + path("plain.json")).exit_code, 0);
    Json model = Json::parse(read_text(path("plain.json")));
    model["reading_std"] = {{"gauge", kNoise / std::sqrt(3.0)}};
    write(path("M.json"), model.dump(2));
    const auto sim =
        run_cli("simulate --model " + path("M.json") +
                " --poses 100 --noise-half-width 0.0125 --seed 5 --solver gn --validation 1 "
                "--write-data " +
                path("all.csv"));
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
    std::istringstream all(read_text(path("all.csv")));
    std::ofstream calibration(path("D.csv")), held_out(path("H.csv"));
    std::string line;
    int row = -1;  // the header is row -1
    while (std::getline(all, line)) {
      if (line.empty() || line[0] == '#') continue;
      if (row < 0 || row < 60) calibration << line << "\n";
      if (row < 0 || row >= 60) held_out << line << "\n";
      ++row;
    }
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string path(const std::string& file) { return *dir_ / file; }
  static TempDir* dir_;
};
TempDir* CliPrior::dir_ = nullptr;

TEST_F(CliPrior, CalibrateReportsThePosterior) {
  const std::string r0 = path("R0.json"), r1 = path("R1.json");
  const auto plain = run_cli("calibrate --model " + path("M.json") + " --data " + path("D.csv") +
                             " --report " + r0);
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  const auto map = run_cli("calibrate --model " + path("M.json") + " --data " + path("D.csv") +
                           " --prior-std 'leg*=2.887' --report " + r1);
  ASSERT_EQ(map.exit_code, 0) << map.err;
  EXPECT_NE(map.out.find("MAP estimate"), std::string::npos) << map.out;
  const Json a = Json::parse(read_text(r0)), b = Json::parse(read_text(r1));
  EXPECT_EQ(a["prior"], false);
  EXPECT_EQ(b["prior"], true);
  EXPECT_EQ(b["termination"], "converged");
  const Json truth = Json::parse(read_text(path("all.truth.json")));
  ASSERT_EQ(a["parameters"].size(), b["parameters"].size());
  double weakest_share = 1;
  for (std::size_t i = 0; i < b["parameters"].size(); ++i) {
    const Json& p = b["parameters"][i];
    EXPECT_EQ(p["prior_std"], 2.887) << p["name"];
    EXPECT_TRUE(a["parameters"][i]["prior_std"].is_null());
    EXPECT_EQ(a["parameters"][i]["data_share"], 1.0);
    const double share = p["data_share"].get<double>();
    EXPECT_GE(share, 0);
    EXPECT_LE(share, 1);
    weakest_share = std::min(weakest_share, share);
    // The posterior is tighter than both the prior and the data alone.
    EXPECT_LT(p["std"].get<double>(), 2.887) << p["name"];
    EXPECT_LE(p["std"].get<double>(), a["parameters"][i]["std"].get<double>() * (1 + 1e-9));
  }
  // On this design some parameters are mostly the prior's (docs: weak directions).
  EXPECT_LT(weakest_share, 0.5);
  EXPECT_GT(b["effective_degrees_of_freedom"].get<double>(), 60 - 24);
  EXPECT_LT(b["effective_degrees_of_freedom"].get<double>(), 60);
  EXPECT_EQ(a["effective_degrees_of_freedom"].get<double>(), 36);
  EXPECT_TRUE(b["identifiability"].contains("data_share"));
}

TEST_F(CliPrior, APriorPinsWhatTheDataCannotSee) {
  // Every joint free: 12 directions a single gauge cannot see (docs, section 4).
  const std::string args =
      "--model " + path("M.json") + " --data " + path("D.csv") + " --free '*' --fix 'gauge.*'";
  const auto refused = run_cli("calibrate " + args);
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("determine only"), std::string::npos) << refused.err;
  const auto obs = run_cli("observability " + args + " --prior-std '*=1'");
  ASSERT_EQ(obs.exit_code, 0) << obs.err;
  EXPECT_NE(obs.out.find("with the prior: numerical rank 42 of 42"), std::string::npos) << obs.out;
  EXPECT_NE(obs.out.find("not seen by the data, determined by the prior"), std::string::npos)
      << obs.out;
  EXPECT_EQ(obs.out.find("cannot be determined"), std::string::npos) << obs.out;
  const auto json = run_cli("observability " + args + " --prior-std '*=1' --json -");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const Json a = Json::parse(json.out);
  EXPECT_EQ(a["numerical_rank_with_prior"], 42);
  EXPECT_LT(a["numerical_rank"].get<int>(), 42);
  ASSERT_EQ(a["data_share"].size(), 42u);
  for (const auto& c : a["combinations"]) EXPECT_EQ(c["determined_by_prior"], true);
  const std::string r = path("R_all.json");
  const auto solved = run_cli("calibrate " + args + " --prior-std '*=1' --json " + r);
  ASSERT_EQ(solved.exit_code, 0) << solved.err;
  EXPECT_NE(solved.err.find("the prior determines the rest"), std::string::npos) << solved.err;
  EXPECT_EQ(Json::parse(read_text(r))["parameters"].size(), 42u);
}

TEST_F(CliPrior, BadPriorsGiveOneLineAndExitCode2) {
  const std::string base = "calibrate --model " + path("M.json") + " --data " + path("D.csv");
  for (const std::string bad :
       {"--prior-std 'leg1.base.z=-1'", "--prior-std 'leg1.base.z=abc'",
        "--prior-std 'leg1.base.z=0'", "--prior-std 'nothing.here=1'", "--prior-std leg1.base.z",
        "--prior-std 'leg1.base.z=1rad'", "--prior-std 'leg*=1' --loss huber:0.02"}) {
    const auto r = run_cli(base + " " + bad);
    EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << bad << ": " << r.err;
    EXPECT_NE(r.err.find("error:"), std::string::npos) << r.err;
  }
  // Without the readings' noise a prior has nothing to weigh against.
  const auto unweighted = run_cli("calibrate --model " + path("plain.json") + " --data " +
                                  path("D.csv") + " --prior-std 'leg*=2'");
  EXPECT_EQ(unweighted.exit_code, 2);
  EXPECT_EQ(count_lines(unweighted.err), 1) << unweighted.err;
  EXPECT_NE(unweighted.err.find("reading_std"), std::string::npos) << unweighted.err;
}

TEST_F(CliPrior, SimulateWithAPriorKeepsItsJsonFields) {
  const auto plain = run_cli("simulate --case 4 --seed 3 --validation 50 --json -");
  const auto map = run_cli("simulate --case 4 --seed 3 --validation 50 --prior-std 2.887 --json -");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  ASSERT_EQ(map.exit_code, 0) << map.err;
  const Json a = Json::parse(plain.out), b = Json::parse(map.out);
  for (const auto& [key, value] : a.items()) EXPECT_TRUE(b.contains(key)) << key;
  for (const auto& [key, value] : a["scenario"].items()) EXPECT_TRUE(b["scenario"].contains(key));
  EXPECT_EQ(b["scenario"]["prior_std_mm"], 2.887);
  EXPECT_TRUE(a["scenario"]["prior_std_mm"].is_null());
  // Same scenario, same truth: only the estimate differs.
  EXPECT_EQ(a["parameters"][0]["true"], b["parameters"][0]["true"]);
  EXPECT_NE(a["parameters"][0]["estimate"], b["parameters"][0]["estimate"]);
  for (const std::string bad :
       {"--prior-std 0", "--prior-std -1mm", "--prior-std x", "--prior-std 0.01rad"}) {
    const auto r = run_cli("simulate --case 4 --validation 1 " + bad);
    EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << bad << ": " << r.err;
  }
  const auto noiseless = run_cli("simulate --case 1 --validation 1 --prior-std 2.887");
  EXPECT_EQ(noiseless.exit_code, 2);
  EXPECT_EQ(count_lines(noiseless.err), 1) << noiseless.err;
  EXPECT_NE(noiseless.err.find("noise"), std::string::npos) << noiseless.err;
}

TEST_F(CliPrior, ValidateOnHeldOutData) {
  const std::string c = path("C.json"), r = path("R.json"), v = path("V.json");
  ASSERT_EQ(run_cli("calibrate --model " + path("M.json") + " --data " + path("D.csv") +
                    " --prior-std 'leg*=2.887' --out " + c + " --report " + r)
                .exit_code,
            0);
  const auto run = run_cli("validate --model " + c + " --data " + path("H.csv") + " --report " + r +
                           " --json " + v);
  EXPECT_EQ(run.exit_code, 0) << run.err << run.out;
  EXPECT_NE(run.out.find("consistent"), std::string::npos) << run.out;
  const Json j = Json::parse(read_text(v));
  EXPECT_EQ(j["format"], "kincal-validation");
  EXPECT_EQ(j["configurations"], 40);
  EXPECT_EQ(j["readings"], 40);
  EXPECT_EQ(j["verdict"], "consistent");
  EXPECT_EQ(j["parameter_uncertainty"], true);
  EXPECT_EQ(j["noise"], "sigma_hat x reading_std");
  EXPECT_GT(j["per_reading"][0]["parameter_rms"].get<double>(), 0);
  EXPECT_GT(j["per_reading"][0]["predicted_rms"].get<double>(),
            j["per_reading"][0]["noise_std"].get<double>());
  EXPECT_EQ(j["residuals"].size(), 40u);
  // A gauge measures no point: "consistent" is about its readings, and says so (issue 21).
  EXPECT_EQ(j["pose_accuracy_shown"], false);
  EXPECT_NE(j["pose_accuracy_note"].get<std::string>().find("does not confirm its pose accuracy"),
            std::string::npos);
  EXPECT_NE(run.out.find("note: these held-out readings measure no point"), std::string::npos)
      << run.out;
  // Without the report: the stated noise alone.
  const auto noise_only =
      run_cli("validate --model " + c + " --data " + path("H.csv") + " --json -");
  EXPECT_LE(noise_only.exit_code, 1) << noise_only.err;
  EXPECT_EQ(Json::parse(noise_only.out)["noise"], "reading_std");
  // The nominal model predicts the held-out readings far worse than its noise: exit code 1.
  const auto nominal = run_cli("validate --model " + path("M.json") + " --data " + path("H.csv"));
  EXPECT_EQ(nominal.exit_code, 1) << nominal.out << nominal.err;
  EXPECT_NE(nominal.out.find("NOT consistent"), std::string::npos) << nominal.out;
}

TEST_F(CliPrior, ValidateBadInput) {
  const std::vector<std::string> bad = {
      "validate --model " + path("M.json"),
      "validate --data " + path("H.csv"),
      "validate --model " + path("M.json") + " --data " + path("H.csv") + " --report " +
          path("M.json"),
      "validate --model " + path("M.json") + " --data " + path("H.csv") + " --json " +
          path("H.csv"),
  };
  for (const auto& args : bad) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << args << ": " << r.err;
  }
}

// Without reading_std and without a report nothing predicts the residuals: they are
// reported all the same (issue 20: a nominal model validates), the test is not made.
TEST_F(CliPrior, ValidateWithoutAPredictionReportsTheResidualsUntested) {
  const auto r =
      run_cli("validate --model " + path("plain.json") + " --data " + path("H.csv") + " --json -");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json j = Json::parse(r.out);
  EXPECT_EQ(j["verdict"], "not_tested");
  EXPECT_TRUE(j["chi_square"].is_null());
  EXPECT_TRUE(j["noise"].is_null());
  EXPECT_GT(j["residual_rms"].get<double>(), 0);
  EXPECT_FALSE(j.contains("position_error_mm"));  // a length gauge measures no point
}

}  // namespace
}  // namespace kincal
