// kincal run PROJECT.yaml (cli/command_run.cpp): the steps run as their commands, paths
// relative to the file whatever the working directory, every step's options checked before
// the first runs, the report records the project, --from-report redoes the run. That a
// project writes the same files as its command sequence is held by the examples
// (examples/hexapod-gauge/run.py and the two real-data scripts).

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "kincal/framework/io/sha256.hpp"

namespace {

using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;
namespace fs = std::filesystem;

const char* const kProject = R"(name: a small hexapod calibration
variables:
  out: results
steps:
  - model:
      preset: cube-hexapod
      out: ${out}/nominal.json
  - simulate:
      model: ${out}/nominal.json
      case: 5
      seed: 7
      write-data: ${out}/measured.csv
  - calibrate:
      model: ${out}/nominal.json
      data: ${out}/measured.csv
      out: ${out}/calibrated.json
      json: ${out}/report.json
)";

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

TEST(ProjectRun, RunsItsStepsWithPathsRelativeToTheFile) {
  TempDir dir("project-run");
  fs::create_directories(dir.path() / "proj" / "results");
  write(dir / "proj/p.yaml", kProject);
  // From another folder: the outputs land beside the project file.
  const auto run = run_cli("run proj/p.yaml", "cd " + dir.path().string() + " && ");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("kincal run: step 3/3: kincal calibrate --model "), std::string::npos)
      << run.err;
  ASSERT_TRUE(fs::exists(dir / "proj/results/calibrated.json"));
  const auto report = nlohmann::json::parse(read_text(dir / "proj/results/report.json"));
  ASSERT_TRUE(report.contains("project"));
  EXPECT_EQ(report["project"]["sha256"], kincal::sha256_hex(kProject));
  EXPECT_EQ(report["project"]["content"], kProject);
  EXPECT_EQ(report["project"]["step"], 3);
  EXPECT_EQ(report["project"]["variables"]["out"], "results");

  // The record redoes the run: the same calibrated model, bit for bit.
  const std::string first = read_text(dir / "proj/results/calibrated.json");
  fs::remove(dir / "proj/results/calibrated.json");
  const auto again = run_cli("run --from-report " + (dir / "proj/results/report.json"));
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(read_text(dir / "proj/results/calibrated.json"), first);
}

TEST(ProjectRun, AMisspeltKeyStopsBeforeAnyStepRuns) {
  TempDir dir("project-typo");
  std::string text = kProject;
  text.replace(text.find("      seed: 7"), 13, "      seeed: 7");
  write(dir / "p.yaml", text);
  const auto run = run_cli("run " + (dir / "p.yaml"));
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.err, "kincal run: error: " + (dir / "p.yaml") +
                         ":11: steps[2].simulate: unrecognised option '--seeed'; did you mean "
                         "--seed?\n");
  // Step 1 did not run: nothing written.
  EXPECT_FALSE(fs::exists(dir / "results/nominal.json"));
}

TEST(ProjectRun, AFailingStepStopsTheRunAtItsLine) {
  TempDir dir("project-fails");
  write(dir / "p.yaml",
        "steps:\n  - calibrate:\n      model: missing.json\n      data: d.csv\n"
        "  - export:\n      model: missing.json\n      format: csv\n");
  const auto run = run_cli("run " + (dir / "p.yaml"));
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("kincal run: error: " + (dir / "p.yaml") + ":3: steps[1].calibrate: " +
                         (dir / "missing.json") + ": cannot open model file"),
            std::string::npos)
      << run.err;
  EXPECT_EQ(run.err.find("step 2/2"), std::string::npos) << run.err;
}

TEST(ProjectRun, DryRunPrintsTheCommandsAndWritesNothing) {
  TempDir dir("project-dry");
  write(dir / "p.yaml", kProject);
  const auto run = run_cli("run " + (dir / "p.yaml") + " --dry-run --set out=elsewhere");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("kincal model --preset cube-hexapod --out " + (dir / "elsewhere") +
                         "/nominal.json\n"),
            std::string::npos)
      << run.out;
  EXPECT_FALSE(fs::exists(dir / "elsewhere"));
}

TEST(ProjectRun, EachStepIsOneShellLineWhateverItsValuesHold) {
  TempDir dir("project-words");
  // A line break and quotes in a value: printed as a shell would take the word back.
  write(dir / "p.yaml",
        "steps:\n  - export:\n      model: \"m\\nx'y.json\"\n      format: \"it's\"\n");
  const auto run = run_cli("run " + (dir / "p.yaml") + " --dry-run");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.out,
            "kincal export --model $'" + (dir / "m") + "\\x0Ax\\x27y.json' --format 'it'\\''s'\n");
}

TEST(ProjectRun, ProjectErrorsAreOneLine) {
  TempDir dir("project-errors");
  write(dir / "p.yaml", "steps:\n  - calibrat: {}\n  - run: {}\n");
  const auto unknown = run_cli("run " + (dir / "p.yaml"));
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_EQ(unknown.err, "kincal run: error: " + (dir / "p.yaml") +
                             ":2: steps[1].calibrat: 'calibrat' is not a command a project can "
                             "run (did you mean 'calibrate'?); expected one of kincal's "
                             "commands (kincal --help) other than run\n");
  write(dir / "q.yaml", "steps:\n  - run: {}\n");
  const auto nested = run_cli("run " + (dir / "q.yaml"));
  EXPECT_EQ(nested.exit_code, 2);
  EXPECT_NE(nested.err.find("'run' is not a command a project can run"), std::string::npos);
  const auto none = run_cli("run");
  EXPECT_EQ(none.err, "kincal run: error: expected the project file: kincal run PROJECT.yaml\n");
  const auto missing = run_cli("run " + (dir / "nothere.yaml"));
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("cannot open project file (YAML)"), std::string::npos) << missing.err;
  const auto bad_set = run_cli("run " + (dir / "p.yaml") + " --set nothing");
  EXPECT_EQ(bad_set.err, "kincal run: error: --set 'nothing': expected NAME=VALUE\n");
}

TEST(ProjectRun, KeepGoingRunsPastAVerdict) {
  TempDir dir("project-keep-going");
  write(dir / "p.yaml", kProject);
  ASSERT_EQ(run_cli("run " + (dir / "p.yaml")).exit_code, 0);
  // A model that is not the report's: verify exits with 1, a verdict.
  write(dir / "q.yaml",
        "steps:\n  - verify:\n      report: results/report.json\n      model: "
        "results/nominal.json\n  - export:\n      model: results/calibrated.json\n      format: "
        "csv\n      out: results/joints.csv\n");
  const auto stopped = run_cli("run " + (dir / "q.yaml"));
  EXPECT_EQ(stopped.exit_code, 1);
  EXPECT_NE(stopped.err.find("steps[1].verify exited with 1; the later steps were not run"),
            std::string::npos)
      << stopped.err;
  EXPECT_FALSE(fs::exists(dir / "results/joints.csv"));
  const auto going = run_cli("run " + (dir / "q.yaml") + " --keep-going");
  EXPECT_EQ(going.exit_code, 1);
  EXPECT_TRUE(fs::exists(dir / "results/joints.csv"));
  // A calibration not to load (3, a target one gauge cannot meet) is a verdict too.
  write(dir / "r.yaml",
        "steps:\n  - calibrate:\n      model: results/nominal.json\n      data: "
        "results/measured.csv\n      target: 0.05mm\n      out: results/strict.json\n  - "
        "export:\n      model: results/strict.json\n      format: csv\n      out: "
        "results/strict.csv\n");
  const auto strict = run_cli("run " + (dir / "r.yaml") + " --keep-going");
  EXPECT_EQ(strict.exit_code, 3) << strict.err;
  EXPECT_NE(strict.err.find("steps[1].calibrate exited with 3; running the later steps"),
            std::string::npos)
      << strict.err;
  EXPECT_TRUE(fs::exists(dir / "results/strict.csv"));
}

}  // namespace
