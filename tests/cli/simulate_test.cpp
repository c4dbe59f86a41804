// kincal list / simulate / reproduce through the real binary.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_runner.hpp"

namespace kincal {
namespace {

using kincal::testing::count_lines;
using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;

TEST(CliList, ListsSolversAndModels) {
  const auto solvers = run_cli("list solvers");
  EXPECT_EQ(solvers.exit_code, 0);
  EXPECT_NE(solvers.out.find("gn "), std::string::npos) << solvers.out;
  const auto models = run_cli("list models");
  EXPECT_EQ(models.exit_code, 0);
  EXPECT_NE(models.out.find("cube-hexapod"), std::string::npos);
  const auto bad = run_cli("list widgets");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(count_lines(bad.err), 1) << bad.err;
}

TEST(CliSimulate, JsonHasTheDocumentedFields) {
  const auto r = run_cli("simulate --case 1 --solver gn --validation 20 --json -");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["solver"], "gn");
  EXPECT_EQ(j["termination"], "converged");
  EXPECT_GT(j["iterations"].get<int>(), 0);
  EXPECT_GE(j["solve_seconds"].get<double>(), 0.0);
  EXPECT_GT(j["initial_cost"].get<double>(), j["final_cost"].get<double>());
  ASSERT_EQ(j["parameters"].size(), 24u);
  for (const auto& p : j["parameters"]) {
    EXPECT_TRUE(p.contains("name") && p.contains("nominal"));
    EXPECT_NEAR(p["estimate"].get<double>(), p["true"].get<double>(), 1e-6) << p["name"];
  }
  for (const char* phase : {"before", "after"})
    for (const char* field :
         {"position_mean_mm", "position_max_mm", "orientation_mean_rad", "orientation_max_rad"})
      EXPECT_TRUE(j["validation"][phase][field].is_number()) << phase << " " << field;
  EXPECT_LT(j["validation"]["after"]["position_max_mm"].get<double>(), 1e-6);
  ASSERT_EQ(j["trace"].size(), static_cast<std::size_t>(j["iterations"].get<int>() + 1));
  EXPECT_EQ(j["trace"][0]["iteration"], 0);
  EXPECT_TRUE(j["trace"][0]["position_mean_mm"].is_number());
  EXPECT_TRUE(j["trace"][0]["orientation_mean_rad"].is_number());
  EXPECT_TRUE(j["trace"][0]["cost"].is_number());
}

// Case 4 from +-20 mm, seed 95: the implicit solve stalls and the nested one from the same
// start replaces it (calibration_solve.hpp). The JSON is the nested solve's, its trace
// included, and says why.
TEST(CliSimulate, AFailedImplicitSolveIsReportedAsTheNestedOneWithTheReason) {
  if (run_cli("list solvers").out.find("lm ") == std::string::npos)
    GTEST_SKIP() << "lm backend not built";
  const std::string args = "simulate --case 4 --param-error 20mm --seed 95 --validation 10 ";
  const auto implicit = run_cli(args + "--formulation implicit --json -");
  ASSERT_EQ(implicit.exit_code, 0) << implicit.err;
  const auto nested = run_cli(args + "--json -");
  ASSERT_EQ(nested.exit_code, 0) << nested.err;
  const auto j = nlohmann::json::parse(implicit.out), n = nlohmann::json::parse(nested.out);
  EXPECT_EQ(j["formulation"], "nested");
  const std::string note = j["formulation_note"];
  EXPECT_NE(note.find("implicit formulation failed after"), std::string::npos) << note;
  EXPECT_NE(note.find("solved nested from the same start"), std::string::npos) << note;
  EXPECT_NE(implicit.err.find(note), std::string::npos) << implicit.err;
  EXPECT_EQ(j["termination"], "converged");
  EXPECT_EQ(j["iterations"], n["iterations"]);
  EXPECT_EQ(j["final_cost"], n["final_cost"]);
  EXPECT_EQ(j["parameters"], n["parameters"]);
  // The validation errors along the trace are those of the nested solve's iterates.
  ASSERT_EQ(j["trace"].size(), n["trace"].size());
  for (std::size_t i = 0; i < n["trace"].size(); ++i)
    for (const char* field : {"cost", "position_mean_mm", "orientation_mean_rad"})
      EXPECT_EQ(j["trace"][i][field], n["trace"][i][field]) << i << " " << field;
  EXPECT_EQ(n["formulation_note"], "");
}

TEST(CliSimulate, SameSeedSameOutputAndFilesWritten) {
  TempDir dir("simulate");
  const std::string args = "simulate --case 4 --solver gn --seed 17 --validation 10 --json " +
                           (dir / "a.json") + " --trace " + (dir / "a.csv");
  const auto first = run_cli(args);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_NE(first.out.find("case 4"), std::string::npos);
  auto a = nlohmann::json::parse(read_text(dir / "a.json"));
  const std::string trace = read_text(dir / "a.csv");
  EXPECT_EQ(trace.rfind("iteration,cost", 0), 0u);
  EXPECT_EQ(count_lines(trace), a["iterations"].get<int>() + 2);
  const auto second = run_cli(args);
  ASSERT_EQ(second.exit_code, 0);
  auto b = nlohmann::json::parse(read_text(dir / "a.json"));
  // Everything but the timings must agree bit for bit.
  for (auto* run : {&a, &b}) {
    run->erase("solve_seconds");
    for (auto& row : (*run)["trace"]) row.erase("seconds");
  }
  EXPECT_EQ(a.dump(), b.dump());
}

// "--param-error 0 zeroes the mm errors and leaves +-0.01 rad" (issue 21): a bare 0 is the
// truth itself, in every unit; "0mm" still leaves the angles' default.
TEST(CliSimulate, ParamErrorZeroIsZeroInEveryUnit) {
  TempDir dir("param-error-zero");
  ASSERT_EQ(run_cli("model --preset puma560 --out " + dir / "M.json").exit_code, 0);
  const auto truth_of = [&](const std::string& error) {
    const auto r = run_cli("simulate --model " + dir / "M.json" + " --param-error " + error +
                           " --poses 40 --validation 1 --write-data " + dir / "D.csv");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(read_text(dir / "D.truth.json"));
  };
  const auto model = nlohmann::json::parse(read_text(dir / "M.json"));
  EXPECT_EQ(truth_of("0")["mechanism"], model["mechanism"]);
  EXPECT_EQ(truth_of("0.0")["mechanism"], model["mechanism"]);
  EXPECT_NE(truth_of("0mm")["mechanism"], model["mechanism"]);  // angles still drawn
}

TEST(CliSimulate, BadOptionsGiveOneLineAndExitCode2) {
  for (const char* args :
       {"simulate --case 7",
        "simulate --poses abc",
        "simulate --solver nope",
        "simulate --case 2 --poses 10",
        "simulate --noise -1",
        "simulate --bogus",
        "simulate --solver gn --solver-option nokey",
        "simulate --solver gn --solver-option a=1",
        "simulate --validation 0",
        "simulate --json /dev/null/x.json",
        "frobnicate",
        "simulate --case 1 stray words",
        "reproduce --trials 1 junk",
        "simulate --seed -1",
        "simulate --seed 1.5",
        "observability --poses 30 --seed -2",
        "simulate --json .",
        "simulate --poses 10 --solver gn",
        "simulate --solver-option initial_trust_radius=1 --solver-option initial_trust_radius=2",
        "simulate --verbose=3"}) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_EQ(count_lines(r.err), 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find("error"), std::string::npos) << args;
  }
}

TEST(CliReproduce, WritesTablesForAllFiveCases) {
  TempDir dir("reproduce");
  const auto r = run_cli("reproduce --trials 3 --solver gn --validation 10 --threads 2 --out " +
                         dir.path().string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* c : {"\n1 ", "\n2 ", "\n3 ", "\n4 ", "\n5 "})
    EXPECT_NE(r.out.find(c), std::string::npos) << r.out;
  const std::string summary = read_text(dir / "summary.csv");
  EXPECT_EQ(count_lines(summary), 6);
  // The error before calibration in both measures, and unreachable validation poses.
  for (const char* column : {"position_before_median_mm", "orientation_before_median_rad",
                             "trials_with_unreachable_validation_poses"})
    EXPECT_NE(summary.find(column), std::string::npos) << column;
  EXPECT_NE(r.out.find("unreachable"), std::string::npos) << r.out;
  EXPECT_EQ(count_lines(read_text(dir / "trials.csv")), 1 + 5 * 3);
  EXPECT_GT(count_lines(read_text(dir / "trace.csv")), 5);
}

TEST(CliReproduce, ResultsDoNotDependOnTheThreadCount) {
  TempDir dir("reproduce-threads");
  const std::string common = "reproduce --trials 4 --solver gn --validation 10 --out ";
  ASSERT_EQ(run_cli(common + (dir / "one") + " --threads 1").exit_code, 0);
  ASSERT_EQ(run_cli(common + (dir / "two") + " --threads 2").exit_code, 0);
  EXPECT_EQ(read_text(dir / "one/summary.csv"), read_text(dir / "two/summary.csv"));
  EXPECT_EQ(read_text(dir / "one/trace.csv"), read_text(dir / "two/trace.csv"));
}

}  // namespace
}  // namespace kincal
