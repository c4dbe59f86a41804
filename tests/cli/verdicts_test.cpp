// Issue 19, "wrong results presented as fine": no verdict on NaN, validate's report checked
// (its numbers and its model's SHA-256), design and simulate refusing problems the data
// cannot determine, calibrate --allow-rank-deficient with nothing identifiable, and design's
// memory check. Through the real binary.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_runner.hpp"

namespace kincal {
namespace {

using kincal::testing::CliResult;
using kincal::testing::count_lines;
using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;
using Json = nlohmann::json;
namespace fs = std::filesystem;

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

void expect_one_line_error(const CliResult& r, const std::string& part, const std::string& what) {
  EXPECT_EQ(r.exit_code, 2) << what << ": " << r.err << r.out;
  EXPECT_EQ(count_lines(r.err), 1) << what << ": " << r.err;
  EXPECT_NE(r.err.find(part), std::string::npos) << what << ": " << r.err;
}

// `path` (a JSON file) with `edit` applied, written to `out`.
void edit_json(const std::string& path, const std::string& out,
               const std::function<void(Json&)>& edit) {
  Json j = Json::parse(read_text(path));
  edit(j);
  write(out, j.dump(2));
}

// The cube hexapod stating its gauge's noise; 80 simulated configurations, the first 60 for
// the calibration (C.json, R.json), the last 20 held out (H.csv); a second machine (another
// seed, another truth) calibrated the same way (C2.json, R2.json).
class CliVerdicts : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir("verdicts");
    ASSERT_EQ(run_cli("model --out " + path("plain.json")).exit_code, 0);
    edit_json(path("plain.json"), path("M.json"), [](Json& m) {
      m["reading_std"] = {{"gauge", 0.0125 / std::sqrt(3.0)}};
    });
    for (const std::string machine : {"", "2"}) {
      const auto sim = run_cli(
          "simulate --model " + path("M.json") +
          " --poses 80 --noise-half-width 0.0125 --solver gn --validation 1 --seed " +
          (machine.empty() ? "5" : "6") + " --write-data " + path("all" + machine + ".csv"));
      ASSERT_EQ(sim.exit_code, 0) << sim.err;
      std::istringstream all(read_text(path("all" + machine + ".csv")));
      std::ofstream calibration(path("D" + machine + ".csv")),
          held_out(path("H" + machine + ".csv"));
      std::string line;
      int row = -1;  // the header is row -1
      while (std::getline(all, line)) {
        if (line.empty() || line[0] == '#') continue;
        if (row < 60) calibration << line << "\n";
        if (row < 0 || row >= 60) held_out << line << "\n";
        ++row;
      }
      calibration.close();
      const auto cal = run_cli(
          "calibrate --model " + path("M.json") + " --data " + path("D" + machine + ".csv") +
          " --out " + path("C" + machine + ".json") + " --json " + path("R" + machine + ".json"));
      ASSERT_EQ(cal.exit_code, 0) << cal.err;
    }
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string path(const std::string& file) { return *dir_ / file; }
  static TempDir* dir_;
};
TempDir* CliVerdicts::dir_ = nullptr;

// Item 4: "one held-out reading of 1e300 gives 'chi-square -nan ... consistent', exit 0".
TEST_F(CliVerdicts, ValidateGivesNoVerdictOnStatisticsThatAreNotFinite) {
  std::istringstream in(read_text(path("H.csv")));
  std::string text, line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (n == 3) line = line.substr(0, line.rfind(',')) + ",1e300";
    text += line + "\n";
  }
  write(path("Hbad.csv"), text);
  const std::string json = path("Vbad.json");
  for (const std::string& report : {" --report " + path("R.json"), std::string()}) {
    const std::string args =
        "validate --model " + path("C.json") + " --data " + path("Hbad.csv") + report;
    const auto r = run_cli(args + " --json " + json);
    expect_one_line_error(r, "Hbad.csv:3: field 'gauge'", args);
    EXPECT_NE(r.err.find("not finite"), std::string::npos) << r.err;
    EXPECT_EQ(r.out.find("consistent"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(json));
  }
  // The same data without the line: a verdict, as before.
  const auto good = run_cli("validate --model " + path("C.json") + " --data " + path("H.csv") +
                            " --report " + path("R.json"));
  EXPECT_LE(good.exit_code, 1) << good.err;
  EXPECT_EQ(good.out.find("nan"), std::string::npos) << good.out;
}

// Item 4: "a report with sigma_hat 5e-324, a std of 1e300, a negative std or correlations of
// +-5 is accepted".
TEST_F(CliVerdicts, ValidateRefusesReportNumbersItCannotComputeWith) {
  const std::vector<std::pair<std::function<void(Json&)>, std::string>> cases = {
      {[](Json& r) { r["sigma_hat"] = 5e-324; }, ": sigma_hat is 4.94066e-324"},
      {[](Json& r) { r["sigma_hat"] = 1e300; }, ": sigma_hat is 1e+300"},
      {[](Json& r) { r["parameters"][0]["std"] = 1e300; }, ": parameters[0].std is 1e+300"},
      {[](Json& r) { r["parameters"][1]["std"] = -0.5; }, ": parameters[1].std is -0.5"},
      {[](Json& r) { r["correlation"][0][1] = 5; }, ": correlation[0][1] is 5"},
      {[](Json& r) { r["correlation"][2][0] = -5; }, ": correlation[2][0] is -5"},
  };
  int k = 0;
  for (const auto& [edit, message] : cases) {
    const std::string report = path("Rbad" + std::to_string(k++) + ".json");
    edit_json(path("R.json"), report, edit);
    const auto r = run_cli("validate --model " + path("C.json") + " --data " + path("H.csv") +
                           " --report " + report);
    expect_one_line_error(r, fs::path(report).filename().string() + message, message);
    EXPECT_EQ(r.out, "") << message;
  }
}

// Item 5: "model A with machine B's report gives 'consistent', exit 0, where verify on the
// same pair exits 1".
TEST_F(CliVerdicts, ValidateRefusesTheReportOfAnotherModel) {
  const std::string json = path("V.json");
  const auto mixed = run_cli("validate --model " + path("C.json") + " --data " + path("H.csv") +
                             " --report " + path("R2.json") + " --json " + json);
  expect_one_line_error(mixed, "C.json is not the calibrated model", "model A, report B");
  EXPECT_NE(mixed.err.find("R2.json"), std::string::npos) << mixed.err;
  EXPECT_NE(mixed.err.find("SHA-256"), std::string::npos) << mixed.err;
  EXPECT_EQ(mixed.out, "");
  EXPECT_FALSE(fs::exists(json));
  EXPECT_EQ(run_cli("verify --report " + path("R2.json") + " --model " + path("C.json")).exit_code,
            1);
  // The nominal model is not the calibrated one either.
  expect_one_line_error(run_cli("validate --model " + path("M.json") + " --data " + path("H.csv") +
                                " --report " + path("R.json")),
                        "M.json is not the calibrated model", "nominal model");
  // Each machine's own pair is checked, and passes.
  for (const std::string machine : {"", "2"}) {
    const auto own =
        run_cli("validate --model " + path("C" + machine + ".json") + " --data " +
                path("H" + machine + ".csv") + " --report " + path("R" + machine + ".json"));
    EXPECT_LE(own.exit_code, 1) << own.err;
    EXPECT_EQ(own.err.find("not the calibrated model"), std::string::npos) << own.err;
  }
  // A report written without --out names no model: validate says it cannot check the pair.
  edit_json(path("R.json"), path("Rnull.json"), [](Json& r) { r["calibrated_model"] = nullptr; });
  const auto unnamed = run_cli("validate --model " + path("C.json") + " --data " + path("H.csv") +
                               " --report " + path("Rnull.json"));
  EXPECT_LE(unnamed.exit_code, 1) << unnamed.err;
  EXPECT_NE(unnamed.err.find("names no calibrated model"), std::string::npos) << unnamed.err;
  edit_json(path("R.json"), path("Rbadmodel.json"),
            [](Json& r) { r["calibrated_model"] = "C.json"; });
  expect_one_line_error(run_cli("validate --model " + path("C.json") + " --data " + path("H.csv") +
                                " --report " + path("Rbadmodel.json")),
                        "Rbadmodel.json: calibrated_model: expected", "malformed calibrated_model");
}

// The puma560 with the tracker's target at the origin of the tool frame: joint 6's angle
// moves nothing any reading sees.
void write_puma_target_at_origin(const TempDir& dir, const std::string& out,
                                 const std::vector<std::string>& free) {
  ASSERT_EQ(run_cli("model --preset puma560 --out " + dir / "puma.json").exit_code, 0);
  edit_json(dir / "puma.json", out, [&](Json& m) {
    m["sensors"][0]["target"] = {0.0, 0.0, 0.0};
    m["free"] = free;
  });
}

// Item 3: "exit 139 (segfault in Eigen's SVD from the report's covariance) when
// --allow-rank-deficient leaves no observable free parameter".
TEST(CliRankDeficient, CalibrateWithNothingIdentifiableIsAnErrorNotACrash) {
  TempDir dir("nothing-identifiable");
  const std::string seen = dir / "seen.json", unseen = dir / "unseen.json", data = dir / "D.csv";
  write_puma_target_at_origin(dir, seen, {"joint1.a"});
  write_puma_target_at_origin(dir, unseen, {"joint6.theta"});
  const auto sim = run_cli("simulate --model " + seen +
                           " --poses 20 --seed 3 --validation 1 --write-data " + data);
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const std::string out = dir / "C.json", report = dir / "R.json";
  const std::string args =
      "calibrate --model " + unseen + " --data " + data + " --out " + out + " --json " + report;
  const auto r = run_cli(args + " --allow-rank-deficient");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  // A note on fixing joint6.theta, then the error.
  EXPECT_LE(count_lines(r.err), 2) << r.err;
  EXPECT_NE(r.err.find("error: " + data + ": no reading depends on free parameter(s) joint6.theta"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("nothing to solve for"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(report));
  // Without the option: the refusal as before.
  expect_one_line_error(run_cli(args), "pass --allow-rank-deficient", "without the option");
}

// Item 7: "simulate --config-range 0mm --poses 40 prints 'lm: converged' and exits 0 on a
// rank-1 problem; calibrate refuses the same data".
TEST(CliRankDeficient, SimulateRefusesWhatCalibrateRefuses) {
  TempDir dir("simulate-rank");
  const std::string json = dir / "S.json", data = dir / "D.csv";
  const auto r = run_cli("simulate --config-range 0mm --poses 40 --seed 1 --validation 10 --json " +
                         json + " --write-data " + data);
  expect_one_line_error(r, "the simulated data (40 configurations, seed 1): ", "config-range 0");
  EXPECT_NE(r.err.find("the data determine only 1 of 24 free parameters"), std::string::npos)
      << r.err;
  EXPECT_EQ(r.out.find("converged"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(json));
  EXPECT_FALSE(fs::exists(data));
  // As calibrate, --allow-rank-deficient solves for what the data determine; calibrate then
  // refuses the data it wrote: noise-free copies of one configuration count once.
  const auto allowed =
      run_cli("simulate --config-range 0mm --poses 40 --seed 1 --validation 10 --json " + json +
              " --write-data " + data + " --allow-rank-deficient");
  // (Whether the one identifiable parameter can explain the readings at home is the
  // solver's to say: exit 0 or 1, every output written.)
  ASSERT_LE(allowed.exit_code, 1) << allowed.err;
  ASSERT_TRUE(fs::exists(data));
  EXPECT_NE(allowed.err.find("are fixed at their model values"), std::string::npos) << allowed.err;
  EXPECT_NE(allowed.out.find("(1 free parameters)"), std::string::npos) << allowed.out;
  const Json result = Json::parse(read_text(json));
  EXPECT_EQ(result["parameters"].size(), 1u);
  EXPECT_EQ(result["fixed_by_identifiability"].size(), 23u);
  ASSERT_EQ(run_cli("model --out " + dir / "M.json").exit_code, 0);
  const auto calibrate = run_cli("calibrate --model " + dir / "M.json" + " --data " + data);
  expect_one_line_error(calibrate,
                        "1 usable configurations (39 more row(s) copy one exactly and count "
                        "once) give 1 readings for 24 free parameters",
                        "calibrate on the same data");
}

// Item 6: "design exits 0 on degenerate problems with criterion -inf, NaN predictions, no
// warning, and a template of 30 copies of home".
TEST(CliDesignDegenerate, DegenerateProblemsAreRefused) {
  TempDir dir("design-degenerate");
  const std::string m = dir / "M.json", out = dir / "T.csv", json = dir / "T.json";
  ASSERT_EQ(run_cli("model --out " + m).exit_code, 0);
  const std::string design =
      "design --model " + m + " --poses 30 --candidates 300 --out " + out + " --json " + json + " ";
  expect_one_line_error(run_cli(design + "--config-range 0mm --noise-std 0.0072mm"),
                        "no design of these 364 candidates determines every free parameter: "
                        "no reading depends on free parameter(s) leg4.base.y",
                        "config-range 0");
  for (const std::string noise : {"1e-200mm", "1e-320mm", "1e150mm", "0mm", "-1mm"})
    expect_one_line_error(run_cli(design + "--noise-std " + noise),
                          "--noise-std '" + noise + "': ", noise);
  const std::string puma = dir / "puma-target-at-origin.json";
  write_puma_target_at_origin(dir, puma, {"joint1.a", "joint6.theta"});
  const auto unseen = run_cli("design --model " + puma + " --poses 10 --candidates 300 --out " +
                              out + " --json " + json + " --noise-std 0.01mm");
  expect_one_line_error(unseen, "no reading depends on free parameter(s) joint6.theta",
                        "a parameter no reading sees");
  EXPECT_NE(unseen.err.find("determine only 1 of 2 free parameters"), std::string::npos)
      << unseen.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(json));
  // A prior determines what the readings cannot: then the design is made, and every
  // prediction is a number.
  const auto with_prior =
      run_cli("design --model " + puma + " --poses 10 --candidates 300 --noise-std 0.01mm --out " +
              out + " --json " + json + " --prior-std joint6.theta=0.01");
  ASSERT_EQ(with_prior.exit_code, 0) << with_prior.err;
  const Json j = Json::parse(read_text(json));
  for (const auto& p : j["parameters"]) EXPECT_TRUE(p["designed_std"].is_number()) << p;
  EXPECT_TRUE(j["exchange"]["value"].is_number());
  EXPECT_EQ(with_prior.out.find("nan"), std::string::npos) << with_prior.out;
}

// Item 12: "design does not check memory for its n x n matrices: a 10^4-parameter model
// reaches 2.4 GB and runs on". A 4·10^4-parameter model here.
TEST(CliDesignDegenerate, MemoryForTheMatricesIsCheckedBeforeAnyWork) {
  TempDir dir("design-memory");
  const std::string big = dir / "big.json", out = dir / "T.csv";
  ASSERT_EQ(run_cli("model --preset puma560 --out " + dir / "puma.json").exit_code, 0);
  edit_json(dir / "puma.json", big, [](Json& m) {
    Json joints = Json::array();
    for (int i = 0; i < 10000; ++i)
      joints.push_back({{"name", "j" + std::to_string(i)},
                        {"type", "revolute"},
                        {"convention", "dh"},
                        {"a", 1.0},
                        {"alpha_deg", i % 2 ? 90.0 : -90.0},
                        {"d", 1.0},
                        {"theta_deg", 0.0},
                        {"home_deg", 10.0}});
    m["mechanism"]["joints"] = joints;
    m["free"] = {"j*.a", "j*.alpha", "j*.d", "j*.theta"};
  });
  // 16 matrices of 4·10^4 x 4·10^4 doubles need 205 GB, beyond any machine this runs on (no
  // ulimit -v: AddressSanitizer reserves terabytes of address space for its shadow).
  const auto r = run_cli("design --model " + big +
                         " --poses 30 --candidates 100 --noise-std 0.01mm --out " + out);
  expect_one_line_error(r, "big.json (40000 free parameters): needs about", "4·10^4 parameters");
  EXPECT_NE(r.err.find("of memory"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("expected at most about"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace kincal
