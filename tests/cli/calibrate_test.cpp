// The file workflow through the real binary: model -> simulate --write-data -> calibrate,
// fk/ik/observability, and every bad input of issue 5 giving one line and a non-zero exit.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <tuple>

#include "cli_runner.hpp"

namespace kincal {
namespace {

using kincal::testing::count_lines;
using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;
using Json = nlohmann::json;

// Value of parameter `name` ("leg4.base.x", "gauge.offset") in a model file.
double model_value(const Json& model, const std::string& name) {
  const auto dot = name.find('.');
  const std::string owner = name.substr(0, dot), rest = name.substr(dot + 1);
  const Json* part = nullptr;
  if (owner.rfind("leg", 0) == 0) {
    part = &model["mechanism"]["legs"][std::stoi(owner.substr(3)) - 1];
  } else {
    for (const auto& s : model["sensors"])
      if (s["name"] == owner) part = &s;
  }
  if (rest == "offset") return (*part)["offset"].get<double>();
  const std::string point = rest.substr(0, rest.find('.'));
  const int axis = rest.back() - 'x';
  return (*part)[point][axis].get<double>();
}

// Every free parameter's estimate lies within `k` of the tool's own standard deviations.
void expect_within_reported_std(const Json& report, const Json& truth, double k) {
  ASSERT_FALSE(report["parameters"].empty());
  for (const auto& p : report["parameters"]) {
    const double std = p["std"].get<double>();
    EXPECT_GT(std, 0) << p["name"];
    const double error = p["estimate"].get<double>() - model_value(truth, p["name"]);
    EXPECT_LT(std::abs(error), k * std) << p["name"] << " error " << error << " std " << std;
  }
}

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

class CliCalibrate : public ::testing::Test {
 protected:
  // A model file and simulated data (60 configurations, paper's case 5 noise).
  void SetUp() override {
    ASSERT_EQ(run_cli("model --out " + m_).exit_code, 0);
    const auto sim =
        run_cli("simulate --model " + m_ +
                " --poses 60 --noise-half-width 0.0125 --seed 5 --solver gn --validation 1 "
                "--write-data " +
                d_);
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
  }
  TempDir dir_{"calibrate"};
  std::string m_ = dir_ / "M.json", d_ = dir_ / "D.csv";
};

TEST_F(CliCalibrate, RecoversTheTruthWithinTheReportedStd) {
  const std::string c = dir_ / "C.json", r = dir_ / "R.json";
  const auto run =
      run_cli("calibrate --model " + m_ + " --data " + d_ + " --out " + c + " --json " + r);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("identifiability"), std::string::npos);
  const Json report = Json::parse(read_text(r));
  const Json truth = Json::parse(read_text(dir_ / "D.truth.json"));
  EXPECT_EQ(report["termination"], "converged");
  EXPECT_EQ(report["configurations"], 60);
  EXPECT_EQ(report["degrees_of_freedom"], 36);
  EXPECT_EQ(report["parameters"].size(), 24u);
  EXPECT_EQ(report["correlation"].size(), 24u);
  EXPECT_EQ(report["residuals"].size(), 60u);
  EXPECT_TRUE(report["residuals"][0].contains("gauge"));
  EXPECT_TRUE(report["residuals"][0]["outlier"].is_boolean());
  EXPECT_EQ(report["residuals"][0]["line"], 4);  // two comment lines and the header first
  EXPECT_LT(report["residual_rms"].get<double>(), 0.0125);
  EXPECT_NEAR(report["sigma_hat"].get<double>(), 0.0125 / std::sqrt(3.0), 0.004);
  EXPECT_EQ(report["identifiability"]["numerical_rank"], 24);
  EXPECT_GT(report["identifiability"]["condition_number"].get<double>(), 1);
  for (const char* key : {"O1", "O2", "O3", "O4", "O5", "singular_values", "rank_threshold"})
    EXPECT_TRUE(report["identifiability"].contains(key)) << key;
  expect_within_reported_std(report, truth, 4.5);

  // The calibrated model is a valid input everywhere a model is accepted.
  EXPECT_EQ(run_cli("fk --model " + c + " --actuators 354,354,354,354,354,382").exit_code, 0);
  EXPECT_EQ(run_cli("ik --model " + c + " --pose 0,0,410,0,0,0").exit_code, 0);
  EXPECT_EQ(run_cli("observability --model " + c + " --poses 40").exit_code, 0);
  const auto again = run_cli("calibrate --model " + c + " --data " + d_ + " --solver gn");
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(run_cli("simulate --model " + c + " --poses 30 --solver gn --validation 1").exit_code,
            0);
}

TEST(CliCalibrateOffsets, GaugeAndLegOffsetsFreeAreRecovered) {
  TempDir dir("calibrate-offsets");
  const std::string m = dir / "M.json", d = dir / "D.csv", r = dir / "R.json";
  ASSERT_EQ(run_cli("model --free 'leg*.offset' --free gauge.offset --out " + m).exit_code, 0);
  // All 31 parameters are jointly identifiable on this hexapod: check before calibrating.
  const auto obs = run_cli("observability --model " + m + " --poses 80 --seed 2 --json -");
  ASSERT_EQ(obs.exit_code, 0) << obs.err;
  const Json a = Json::parse(obs.out);
  EXPECT_EQ(a["parameters"], 31);
  EXPECT_EQ(a["numerical_rank"], 31);
  ASSERT_EQ(run_cli("simulate --model " + m +
                    " --poses 80 --noise-half-width 0.00125 --seed 2 --solver gn --validation 1 "
                    "--write-data " +
                    d)
                .exit_code,
            0);
  const auto run = run_cli("calibrate --model " + m + " --data " + d + " --json " + r);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Json report = Json::parse(read_text(r));
  EXPECT_EQ(report["parameters"].size(), 31u);
  expect_within_reported_std(report, Json::parse(read_text(dir / "D.truth.json")), 4.5);
}

TEST_F(CliCalibrate, RankDeficiencyStopsUnlessAllowed) {
  // Every joint free: the base and platform frames themselves cannot be located.
  const auto stop = run_cli("calibrate --model " + m_ + " --data " + d_ + " --free 'leg*'");
  EXPECT_EQ(stop.exit_code, 2);
  EXPECT_EQ(count_lines(stop.err), 1) << stop.err;
  EXPECT_NE(stop.err.find("cannot separate"), std::string::npos) << stop.err;
  EXPECT_NE(stop.err.find("--allow-rank-deficient"), std::string::npos);
  const std::string r = dir_ / "R.json", c = dir_ / "C.json";
  const auto go = run_cli("calibrate --model " + m_ + " --data " + d_ +
                          " --free 'leg*' --allow-rank-deficient --report " + r + " --out " + c);
  ASSERT_EQ(go.exit_code, 0) << go.err;
  const Json report = Json::parse(read_text(r));
  EXPECT_FALSE(report["fixed_by_identifiability"].empty());
  EXPECT_EQ(report["identifiability"]["numerical_rank"].get<int>(),
            static_cast<int>(report["parameters"].size()));
  // The written model's free list is what was estimated, so it can be fed back as is.
  EXPECT_NE(go.err.find("lists only the " + std::to_string(report["parameters"].size()) +
                        " estimated parameters as free"),
            std::string::npos)
      << go.err;
  const Json written = Json::parse(read_text(c));
  std::vector<std::string> estimated;
  for (const auto& p : report["parameters"]) estimated.push_back(p["name"]);
  EXPECT_EQ(written["free"].get<std::vector<std::string>>(), estimated);
  const auto again = run_cli("calibrate --model " + c + " --data " + d_);
  EXPECT_EQ(again.exit_code, 0) << again.err;
}

TEST_F(CliCalibrate, RobustLossNeedsABackendThatTakesIt) {
  const auto gn =
      run_cli("calibrate --model " + m_ + " --data " + d_ + " --solver gn --loss huber:0.01");
  EXPECT_EQ(gn.exit_code, 2);
  EXPECT_EQ(count_lines(gn.err), 1) << gn.err;
  EXPECT_NE(gn.err.find("--loss"), std::string::npos);
  const auto bad = run_cli("calibrate --model " + m_ + " --data " + d_ + " --loss squared:1");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--loss 'squared:1'"), std::string::npos) << bad.err;
  const auto lm = run_cli("list solvers");
  if (lm.out.find("lm ") == std::string::npos) GTEST_SKIP() << "lm backend not built";
  const auto ok = run_cli("calibrate --model " + m_ + " --data " + d_ +
                          " --solver lm --loss cauchy:0.02 --max-iterations 150 " +
                          "--solver-option initial_trust_radius=1e3 --threads 1 --report -");
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const Json with_loss = Json::parse(ok.out);
  EXPECT_EQ(with_loss["loss"], "cauchy:0.02");
  // Every setting in force is in the report (issue 36): limits, tolerances, threads, the loss
  // and the backend's settings, those left at their defaults too.
  const Json& settings = with_loss["solver_options"];
  EXPECT_EQ(settings["max_iterations"], 150);
  EXPECT_EQ(settings["function_tolerance"], 1e-12);
  EXPECT_EQ(settings["gradient_tolerance"], 1e-12);
  EXPECT_EQ(settings["num_threads"], 1);
  EXPECT_EQ(settings["backend_options"]["initial_trust_radius"], "1000");
  EXPECT_EQ(settings["backend_options"]["max_radius_growth"], "10");
  EXPECT_EQ(settings["backend_options"]["linear_solver"], "cholesky");
  EXPECT_FALSE(settings["backend_options"].contains("loss"));
  // The loss has one way in, so the report always names the loss the solve used.
  for (const char* extra : {"", " --loss cauchy:0.02"}) {
    const auto backdoor =
        run_cli("calibrate --model " + m_ + " --data " + d_ +
                " --solver lm --solver-option loss=huber:0.02" + std::string(extra));
    EXPECT_EQ(backdoor.exit_code, 2) << extra;
    EXPECT_EQ(count_lines(backdoor.err), 1) << backdoor.err;
    EXPECT_NE(backdoor.err.find("--solver-option 'loss=huber:0.02': give the robust loss as "
                                "--loss huber:0.02"),
              std::string::npos)
        << backdoor.err;
  }
}

// The JSON report says which formulation was solved and, when it is not the one asked for,
// why, as stderr does (the implicit one needs lm without backend options).
TEST_F(CliCalibrate, TheReportSaysWhichFormulationWasSolvedAndWhy) {
  if (run_cli("list solvers").out.find("lm ") == std::string::npos)
    GTEST_SKIP() << "lm backend not built";
  const std::string base = "calibrate --model " + m_ + " --data " + d_ + " --json - ";
  const auto implicit = run_cli(base + "--formulation implicit");
  ASSERT_EQ(implicit.exit_code, 0) << implicit.err;
  const Json solved = Json::parse(implicit.out);
  EXPECT_EQ(solved["formulation"], "implicit");
  EXPECT_EQ(solved["formulation_note"], "");
  EXPECT_EQ(solved["termination"], "converged");
  const auto by_gn = run_cli(base + "--formulation implicit --solver gn");
  ASSERT_EQ(by_gn.exit_code, 0) << by_gn.err;
  const Json nested = Json::parse(by_gn.out);
  EXPECT_EQ(nested["formulation"], "nested");
  const std::string note = nested["formulation_note"];
  EXPECT_NE(note.find("implicit formulation not used (solver gn does not solve it"),
            std::string::npos)
      << note;
  EXPECT_NE(by_gn.err.find(note), std::string::npos) << by_gn.err;
  const auto by_default = run_cli(base);
  ASSERT_EQ(by_default.exit_code, 0) << by_default.err;
  EXPECT_EQ(Json::parse(by_default.out)["formulation"], "nested");
  EXPECT_EQ(Json::parse(by_default.out)["formulation_note"], "");
}

// Copy of `csv` with `shift` (mm) added to the gauge reading of the given data rows
// (0-based, comments and header not counted).
std::string with_outliers(const std::string& csv, const std::map<int, double>& shift) {
  std::istringstream in(csv);
  std::string line, out;
  int row = -2;  // the header makes it -1, the first data row 0
  while (std::getline(in, line)) {
    if (line[0] != '#' && shift.count(++row)) {
      const auto comma = line.rfind(',');
      char value[64];
      std::snprintf(value, sizeof value, "%.17g",
                    std::stod(line.substr(comma + 1)) + shift.at(row));
      line = line.substr(0, comma + 1) + value;
    }
    out += line + "\n";
  }
  return out;
}

// Gross outliers (about 100 times the noise) in 3 of 60 configurations. The standard
// deviations must come from the robust fit, not from the raw residuals, which made them ~60
// to 120 times the clean-data values. Cauchy discards the outliers: its std is the clean
// one. Huber still gives each outlier a pull of delta, and its estimates really do scatter
// more (measured: tests/framework/robust_uncertainty_test.cpp); its std honestly says so.
TEST_F(CliCalibrate, RobustLossStdIsCloseToTheCleanDataStd) {
  if (run_cli("list solvers").out.find("lm ") == std::string::npos)
    GTEST_SKIP() << "lm backend not built";
  const std::string o = dir_ / "O.csv";
  write(o, with_outliers(read_text(d_), {{5, 1.0}, {23, -0.8}, {41, 1.0}}));
  const std::string clean = dir_ / "clean.json", huber = dir_ / "huber.json",
                    cauchy = dir_ / "cauchy.json", start = dir_ / "H.json";
  ASSERT_EQ(run_cli("calibrate --model " + m_ + " --data " + d_ + " --json " + clean).exit_code, 0);
  const auto h = run_cli("calibrate --model " + m_ + " --data " + o +
                         " --loss huber:0.02 --report " + huber + " --out " + start);
  ASSERT_EQ(h.exit_code, 0) << h.err;
  // Cauchy is not convex: started from the Huber estimate, as docs/calibrating-a-machine.md
  // recommends.
  const auto c = run_cli("calibrate --model " + start + " --data " + o +
                         " --loss cauchy:0.02 --report " + cauchy);
  ASSERT_EQ(c.exit_code, 0) << c.err;
  const Json ref = Json::parse(read_text(clean));
  for (const auto& [file, low, high] :
       {std::tuple{huber, 1.0, 3.0}, std::tuple{cauchy, 0.77, 1.3}}) {
    const Json report = Json::parse(read_text(file));
    EXPECT_NE(report["loss"], "none");
    EXPECT_EQ(report["degrees_of_freedom"], 36);
    EXPECT_GT(report["robust_std_factor"].get<double>(), 1.0);
    int outliers = 0;
    for (const auto& row : report["residuals"]) outliers += row["outlier"].get<bool>();
    EXPECT_EQ(outliers, 3) << file;
    ASSERT_EQ(report["parameters"].size(), ref["parameters"].size());
    for (std::size_t i = 0; i < ref["parameters"].size(); ++i) {
      const double ratio =
          report["parameters"][i]["std"].get<double>() / ref["parameters"][i]["std"].get<double>();
      EXPECT_GT(ratio, low) << file << " " << ref["parameters"][i]["name"];
      EXPECT_LT(ratio, high) << file << " " << ref["parameters"][i]["name"];
    }
  }
}

TEST_F(CliCalibrate, UnreachableRowsAreNamedAndSkippedOnlyWhenAsked) {
  std::string csv = read_text(d_);
  // Line 6 (third data row) gets a negative leg length, line 9 an unreachable one.
  std::vector<std::string> lines;
  std::string::size_type start = 0;
  while (start < csv.size()) {
    const auto end = csv.find('\n', start);
    lines.push_back(csv.substr(start, end - start));
    start = end + 1;
  }
  lines[5] = "-10" + lines[5].substr(lines[5].find(','));
  lines[8] = "5000" + lines[8].substr(lines[8].find(','));
  std::string edited;
  for (const auto& l : lines) edited += l + "\n";
  const std::string bad = dir_ / "bad.csv";
  write(bad, edited);
  const auto stop = run_cli("calibrate --model " + m_ + " --data " + bad);
  EXPECT_EQ(stop.exit_code, 2);
  EXPECT_EQ(count_lines(stop.err), 1) << stop.err;
  EXPECT_NE(stop.err.find("lines 6 ("), std::string::npos) << stop.err;
  EXPECT_NE(stop.err.find(", 9 ("), std::string::npos) << stop.err;
  EXPECT_NE(stop.err.find("--skip-bad-rows"), std::string::npos);
  const std::string r = dir_ / "R.json";
  const auto go =
      run_cli("calibrate --model " + m_ + " --data " + bad + " --skip-bad-rows --json " + r);
  ASSERT_EQ(go.exit_code, 0) << go.err;
  const Json report = Json::parse(read_text(r));
  EXPECT_EQ(report["skipped_lines"], Json::array({6, 9}));
  EXPECT_EQ(report["configurations"], 58);
}

TEST_F(CliCalibrate, BadInputGivesOneLineNamingTheProblemAndExit2) {
  const std::string header = "leg1,leg2,leg3,leg4,leg5,leg6,gauge\n";
  const std::string row = "354,354,354,354,354,382,310\n";
  write(dir_ / "bad.json", "{\"format\": \"kincal-model\",, }");
  write(dir_ / "missing_col.csv", "leg1,leg2,leg3,leg4,leg5,gauge\n354,354,354,354,354,310\n");
  write(dir_ / "dup_col.csv", "leg1,leg2,leg3,leg4,leg5,leg6,leg6,gauge\n");
  write(dir_ / "text.csv", header + row + "354,354,abc,354,354,382,310\n");
  write(dir_ / "nan.csv", header + row + "354,354,354,354,354,382,nan\n");
  write(dir_ / "inf.csv", header + row + "354,354,354,354,354,inf,310\n");
  write(dir_ / "fields.csv", header + row + "354,354,354,354,354,382\n");
  // A missing directory is created when an output is written; a path through a file is not.
  write(dir_ / "plain", "a file, not a directory");
  const std::string no_dir = dir_ / "plain";
  std::string few = header;
  for (int i = 0; i < 10; ++i) few += row;
  write(dir_ / "few.csv", few);
  {
    std::string model = read_text(m_);
    model.replace(model.find("\"offset\": 0.0"), 13, "\"offset\": 1e999");
    write(dir_ / "overflow.json", model);
  }
  const std::string cal = "calibrate --model " + m_ + " --data ";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {cal + dir_ / "none.csv", "none.csv: cannot open measurement file"},
      {"calibrate --model " + dir_ / "none.json" + " --data " + d_,
       "none.json: cannot open model file"},
      {"calibrate --model " + dir_ / "bad.json" + " --data " + d_,
       "bad.json: malformed JSON: parse error at line 1"},
      {cal + dir_ / "missing_col.csv", "missing_col.csv:1: header has no column 'leg6'"},
      {cal + dir_ / "dup_col.csv", "dup_col.csv:1: column 'leg6' appears twice"},
      {cal + dir_ / "text.csv", "text.csv:3: field 'leg3': 'abc' is not a number"},
      {cal + dir_ / "nan.csv", "nan.csv:3: field 'gauge': 'nan' is not a finite number"},
      {cal + dir_ / "inf.csv", "inf.csv:3: field 'leg6': 'inf' is not a finite number"},
      {cal + dir_ / "fields.csv", "fields.csv:3: 6 fields, expected 7"},
      {cal + dir_ / "few.csv",
       "1 usable configurations (9 more row(s) copy one exactly and count once) give 1 "
       "readings for 24 free"},
      {cal + d_ + " --free 'leg9.*'", "--free 'leg9.*': matches no parameter"},
      {cal + d_ + " --fix nope", "--fix 'nope': matches no parameter"},
      {"calibrate --model " + dir_.path().string() + " --data " + d_,
       dir_.path().string() + ": is a directory, expected a model file"},
      {"calibrate --model " + dir_ / "overflow.json" + " --data " + d_,
       "overflow.json: unreadable JSON: number overflow parsing '1e999'"},
      {cal + dir_.path().string(),
       dir_.path().string() + ": is a directory, expected a measurement file"},
      {cal + d_ + " --out " + no_dir + "/C.json",
       "--out '" + no_dir + "/C.json': '" + no_dir + "' is not a directory"},
      {cal + d_ + " --json " + no_dir + "/R.json", "--json '" + no_dir + "/R.json'"},
      {cal + d_ + " --out " + dir_.path().string(), "is a directory, expected a file path"},
      {cal + d_ + " --out " + dir_ / "C.json" + " --json " + dir_ / "./C.json",
       "are the same file"},
      {cal + d_ + " --solver-option loss=huber:1", "give the robust loss as --loss huber:1"},
      {"calibrate --model " + m_, "--data FILE is required"},
      {"fk --model " + m_ + " --actuators 1,2,3", "--actuators '1,2,3': 3 numbers, expected 6"},
      {"fk --model " + m_ + " --actuators -354,354,354,354,354,382", "forward kinematics"},
      {"ik --model " + m_ + " --pose 0,0,410,0,0,x", "field 6 'x' is not a finite number"},
      {"observability --model " + m_, "give exactly one of --data FILE and --poses M"},
      {"model --preset nope", "--preset: unknown model preset 'nope'"},
      {"simulate --model " + dir_ / "bad.json", "bad.json: malformed JSON"},
      {"simulate --write-data " + no_dir + "/D.csv", "--write-data '" + no_dir + "/D.csv'"},
      // Output paths are checked before the model is even read.
      {"simulate --model " + dir_ / "bad.json" + " --json " + no_dir + "/S.json",
       "--json '" + no_dir + "/S.json'"},
      {"simulate --model " + dir_ / "bad.json" + " --trace " + no_dir + "/T.csv",
       "--trace '" + no_dir + "/T.csv'"},
  };
  for (const auto& [args, expected] : cases) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_EQ(count_lines(r.err), 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << args << "\n  got: " << r.err;
  }
}

TEST_F(CliCalibrate, ExistingOutputsSurviveAFailedRun) {
  const std::string c = dir_ / "C.json", r = dir_ / "R.json";
  write(c, "precious model");
  write(r, "precious report");
  const std::string outputs = " --out " + c + " --report " + r;
  // Bad data: stops before solving.
  write(dir_ / "text.csv", "leg1,leg2,leg3,leg4,leg5,leg6,gauge\n1,2,x,4,5,6,7\n");
  const auto bad = run_cli("calibrate --model " + m_ + " --data " + dir_ / "text.csv" + outputs);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(read_text(c), "precious model");
  EXPECT_EQ(read_text(r), "precious report");

  // A failure after the solve: with files limited to 5 KB (10 KB under bash) the calibrated
  // model (~3 KB) can be written but the report (~30 KB) cannot. The model comes first, so
  // writing the files one after the other would replace it and then fail on the report.
  const auto late = run_cli("calibrate --model " + m_ + " --data " + d_ + outputs,
                            kincal::testing::with_file_size_limit(10));
  EXPECT_EQ(late.exit_code, 2);
  EXPECT_NE(late.out.find("parameters:"), std::string::npos) << "did not solve: " << late.err;
  EXPECT_NE(late.err.find("cannot write '" + r + "': File too large"), std::string::npos)
      << late.err;
  EXPECT_EQ(read_text(c), "precious model");
  EXPECT_EQ(read_text(r), "precious report");
  EXPECT_EQ(kincal::testing::count_hidden_files(dir_.path()), 0);

  // A successful run replaces them whole, leaving no temporary files behind.
  ASSERT_EQ(run_cli("calibrate --model " + m_ + " --data " + d_ + outputs).exit_code, 0);
  EXPECT_TRUE(Json::accept(read_text(c)));
  EXPECT_TRUE(Json::accept(read_text(r)));
  EXPECT_EQ(kincal::testing::count_hidden_files(dir_.path()), 0);
}

TEST(CliKinematics, IkAndFkAreInverse) {
  TempDir dir("kinematics");
  const std::string m = dir / "M.json";
  ASSERT_EQ(run_cli("model --out " + m).exit_code, 0);
  const auto ik = run_cli("ik --model " + m + " --pose=-5,3,405,2,-1,10");
  ASSERT_EQ(ik.exit_code, 0) << ik.err;
  std::istringstream in(ik.out);
  std::string name, legs;
  double value;
  for (int i = 0; i < 6 && in >> name >> value; ++i) legs += (i ? "," : "") + std::to_string(value);
  const auto fk = run_cli("fk --model " + m + " --actuators " + legs);
  ASSERT_EQ(fk.exit_code, 0) << fk.err;
  std::istringstream out(fk.out);
  double x, y, z, rx, ry, rz;
  out >> name >> x >> y >> z >> name >> rx >> ry >> rz;
  EXPECT_NEAR(x, -5, 1e-4);
  EXPECT_NEAR(y, 3, 1e-4);
  EXPECT_NEAR(z, 405, 1e-4);
  EXPECT_NEAR(rx, 2, 1e-4);
  EXPECT_NEAR(ry, -1, 1e-4);
  EXPECT_NEAR(rz, 10, 1e-4);
  EXPECT_NE(run_cli("ik --help").out.find("R = Rz(rz) Ry(ry) Rx(rx)"), std::string::npos);
}

}  // namespace
}  // namespace kincal

namespace kincal {
namespace {

// --threads splits the evaluation of 600 configurations over threads (from 256 per thread
// on); the result must not depend on it, to the last digit of the report, and a count out of
// range is one line and a non-zero exit.
TEST(CliThreads, TheResultDoesNotDependOnTheThreadCount) {
  const kincal::testing::TempDir dir("threads");
  const std::string model = dir / "M.json", data = dir / "D.csv";
  ASSERT_EQ(kincal::testing::run_cli("model --out " + model).exit_code, 0);
  const auto sim = kincal::testing::run_cli(
      "simulate --model " + model +
      " --poses 600 --noise-half-width 0.0125 --seed 4 --validation 1 --threads 2 --write-data " +
      data);
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  std::map<int, Json> reports;
  for (const int threads : {1, 2, 3}) {
    const std::string json = dir / ("R" + std::to_string(threads) + ".json");
    const auto run =
        kincal::testing::run_cli("calibrate --model " + model + " --data " + data + " --threads " +
                                 std::to_string(threads) + " --json " + json);
    ASSERT_EQ(run.exit_code, 0) << run.err;
    reports[threads] = Json::parse(kincal::testing::read_text(json));
  }
  for (const int threads : {2, 3}) {
    EXPECT_EQ(reports[threads]["parameters"], reports[1]["parameters"]) << threads;
    EXPECT_EQ(reports[threads]["final_cost"], reports[1]["final_cost"]) << threads;
    EXPECT_EQ(reports[threads]["iterations"], reports[1]["iterations"]) << threads;
  }
  for (const char* bad : {"-1", "1025", "two"}) {
    const auto run = kincal::testing::run_cli("calibrate --model " + model + " --data " + data +
                                              " --threads " + bad);
    EXPECT_NE(run.exit_code, 0) << bad;
    EXPECT_NE(run.err.find("--threads"), std::string::npos) << bad << ": " << run.err;
    EXPECT_EQ(kincal::testing::count_lines(run.err), 1) << run.err;
  }
}

}  // namespace
}  // namespace kincal
