// The project file reader (framework/io/project_file.hpp): what a step becomes on the
// command line, variables and paths, and one-line errors at the right line.

#include "kincal/framework/io/project_file.hpp"

#include <gtest/gtest.h>

#include "kincal/framework/io/sha256.hpp"

namespace kincal {
namespace {

const char* const kProject = R"(# a comment
name: test project
variables:
  out: results
  data: /abs/data
steps:
  - model:
      preset: cube-hexapod
      out: ${out}/nominal.json
  - calibrate:
      model: ${out}/nominal.json
      data: ${data}/measured.csv
      free: [base.*, "tool.x"]
      skip_bad_rows: true
      allow-rank-deficient: false
      solver-option: {max_num_iterations: 50}
      seed: 7
      prior-std: 1mm
  - export:
      model: ${out}/calibrated.json
      format: csv
      out: "-"
)";

std::string error_of(const std::string& text,
                     const std::vector<std::pair<std::string, std::string>>& overrides = {}) {
  try {
    parse_project(text, "/p/proj.yaml", overrides);
  } catch (const ProjectError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ProjectFile, StepsBecomeTheCommandsOptionsInOrder) {
  const Project project = parse_project(kProject, "/p/proj.yaml");
  EXPECT_EQ(project.name, "test project");
  EXPECT_EQ(project.folder, "/p");
  EXPECT_EQ(project.sha256, sha256_hex(kProject));
  ASSERT_EQ(project.steps.size(), 3u);
  EXPECT_EQ(project.steps[0].command, "model");
  EXPECT_EQ(project.steps[0].line, 7);
  EXPECT_EQ(
      project_step_arguments(project.steps[0]),
      (std::vector<std::string>{"--preset", "cube-hexapod", "--out", "/p/results/nominal.json"}));
  // Lists repeat the option, `true` is a switch, `false` leaves it out, maps are KEY=VALUE,
  // underscores become dashes, an absolute path stays, a value that is not a path is as written.
  EXPECT_EQ(project_step_arguments(project.steps[1]),
            (std::vector<std::string>{
                "--model", "/p/results/nominal.json", "--data", "/abs/data/measured.csv", "--free",
                "base.*", "--free", "tool.x", "--skip-bad-rows", "--solver-option",
                "max_num_iterations=50", "--seed", "7", "--prior-std", "1mm"}));
  EXPECT_EQ(project.steps[1].options[4].key, "allow-rank-deficient");
  EXPECT_EQ(project.steps[1].options[4].line, 15);
  // "-" (standard output) is not a path to resolve.
  EXPECT_EQ(project_step_arguments(project.steps[2]).back(), "-");
  EXPECT_EQ(project_step_location(project, 1), "/p/proj.yaml:10: steps[2].calibrate");
}

TEST(ProjectFile, SetReplacesADeclaredVariableOnly) {
  const Project project = parse_project(kProject, "/p/proj.yaml", {{"out", "/elsewhere"}});
  EXPECT_EQ(project.variables.at("out"), "/elsewhere");
  EXPECT_EQ(project_step_arguments(project.steps[0]).back(), "/elsewhere/nominal.json");
  EXPECT_EQ(error_of(kProject, {{"otu", "x"}}),
            "--set otu: /p/proj.yaml declares no variable 'otu' (did you mean 'out'?); it "
            "declares data, out");
}

TEST(ProjectFile, PosesIsAPathOnlyWhereItNamesAFile) {
  EXPECT_TRUE(project_path_option("detect", "poses"));
  EXPECT_TRUE(project_path_option("ik", "poses"));
  EXPECT_FALSE(project_path_option("design", "poses"));
  EXPECT_FALSE(project_path_option("calibrate", "seed"));
  EXPECT_TRUE(project_path_option("design", "candidates-file"));
}

TEST(ProjectFile, ErrorsNameTheFileLineAndKey) {
  EXPECT_EQ(error_of("step:\n  - calibrate: {}\n"),
            "/p/proj.yaml:1: step: not a key of a project (did you mean 'steps'?); expected "
            "name, variables, steps");
  EXPECT_EQ(error_of("steps:\n  - calibrate:\n      data: ${dta}/x.csv\n"),
            "/p/proj.yaml:3: steps[1].calibrate.data: ${dta} is not a variable of this project; "
            "it declares none (variables: {NAME: VALUE})");
  EXPECT_EQ(error_of("variables: {data: d}\nsteps:\n  - calibrate:\n      data: ${dta}/x\n"),
            "/p/proj.yaml:4: steps[1].calibrate.data: ${dta} is not a variable of this project "
            "(did you mean ${data}?); it declares data");
  EXPECT_EQ(error_of("steps:\n  - calibrate:\n      seed: 1\n      seed: 2\n"),
            "/p/proj.yaml:4: steps[1].calibrate: option 'seed' appears twice (give several "
            "values as a list)");
  EXPECT_EQ(error_of("steps:\n  - calibrate:\n      --seed: 1\n"),
            "/p/proj.yaml:3: steps[1].calibrate: '--seed' is not an option name (write it "
            "without the dashes)");
  EXPECT_EQ(error_of("steps: []\n"),
            "/p/proj.yaml:1: steps: expected a non-empty list of steps, e.g. '- calibrate: "
            "{model: M.json, data: D.csv}'");
  EXPECT_EQ(error_of("steps:\n  - calibrate: {}\n    validate: {}\n"),
            "/p/proj.yaml:2: steps[1]: expected one command with its options, e.g. '- "
            "calibrate: {model: M.json, data: D.csv}'");
  EXPECT_EQ(error_of("steps:\n  - calibrate:\n      free: []\n"),
            "/p/proj.yaml:3: steps[1].calibrate.free: an empty list: leave the key out instead");
  EXPECT_EQ(error_of("steps:\n  - calibrate:\n      free: [[a]]\n"),
            "/p/proj.yaml:3: steps[1].calibrate.free: expected a value (text or number), got a "
            "list");
  EXPECT_EQ(error_of("- a\n"),
            "/p/proj.yaml:1: expected a project: a map with 'steps' (and optionally 'name', "
            "'variables')");
  // Braces of ${NAME} in a flow map end the map: the message says to quote.
  const std::string flow = error_of("variables: {o: x}\nsteps:\n  - calibrate: {model: ${o}/m}\n");
  EXPECT_NE(flow.find("/p/proj.yaml:3: malformed YAML"), std::string::npos) << flow;
  EXPECT_NE(flow.find("must be quoted"), std::string::npos) << flow;
  EXPECT_NE(error_of(std::string("steps:\0", 7)).find("NUL byte"), std::string::npos);
  // Not UTF-8 (Latin-1 'é'): refused at its line, since reports record the content as JSON
  // text (the fuzzer's find: the record's dump threw).
  EXPECT_EQ(error_of("steps:\n  - calibrate:\n      data: caf\xe9.csv\n"),
            "/p/proj.yaml:3: not UTF-8 text; expected a project file in UTF-8 (save it as UTF-8)");
  // A key with line breaks (a quoted key) or of any length is quoted on one short line (the
  // fuzzer's second find: the message carried the key's line breaks).
  EXPECT_EQ(error_of("\"st\\neps\": 1\nsteps: [x]\n"),
            "/p/proj.yaml:1: st\\x0Aeps: not a key of a project (did you mean 'steps'?); expected "
            "name, variables, "
            "steps");
  const std::string long_key = error_of("? " + std::string(5000, 'k') + "\n: 1\nsteps: [x]\n");
  EXPECT_LT(long_key.size(), 300u) << long_key;
  EXPECT_NE(long_key.find("kkk...: not a key"), std::string::npos) << long_key;
  // Nesting beyond any project's is refused before it is walked.
  std::string deep = "steps:\n  - calibrate:\n      free: ";
  for (int i = 0; i < 20; ++i) deep += "[";
  deep += "x";
  for (int i = 0; i < 20; ++i) deep += "]";
  EXPECT_NE(error_of(deep + "\n").find("nesting deeper than 8 levels"), std::string::npos);
  // Aliases that would expand to 10^8 values are refused, not walked.
  std::string laughs = "a: &a [x, x, x, x, x, x, x, x, x, x]\n";
  for (char c = 'b'; c <= 'h'; ++c)
    laughs += std::string(1, c) + ": &" + c + " [*" + char(c - 1) + ", *" + char(c - 1) + ", *" +
              char(c - 1) + ", *" + char(c - 1) + ", *" + char(c - 1) + ", *" + char(c - 1) +
              ", *" + char(c - 1) + ", *" + char(c - 1) + ", *" + char(c - 1) + ", *" +
              char(c - 1) + "]\n";
  EXPECT_NE(error_of(laughs + "steps: [*h]\n").find("values (aliases expanded)"),
            std::string::npos);
}

TEST(ProjectFile, JsonWithTheSameKeysReadsTheSame) {
  const std::string json = R"({"variables": {"out": "results"},
    "steps": [{"model": {"preset": "cube-hexapod", "out": "${out}/nominal.json"}}]})";
  const Project project = parse_project(json, "/p/proj.json");
  EXPECT_EQ(
      project_step_arguments(project.steps[0]),
      (std::vector<std::string>{"--preset", "cube-hexapod", "--out", "/p/results/nominal.json"}));
}

TEST(ProjectFile, TheKeyLineOfACommandsMessage) {
  const Project project = parse_project(kProject, "/p/proj.yaml");
  const ProjectStep& step = project.steps[1];
  EXPECT_EQ(project_key_line(step, "--seed '7x': expected a whole number"), 17);
  EXPECT_EQ(project_key_line(step, "/abs/data/measured.csv:3: 6 fields, expected 7"), 12);
  // "--free" is not "--free-something"; an unrelated message is the step's line.
  EXPECT_EQ(project_key_line(step, "--free-x is unknown"), 10);
}

TEST(ProjectFile, AReportsRecordRedoesTheRun) {
  const Project project = parse_project(kProject, "/p/proj.yaml", {{"out", "/o"}});
  nlohmann::ordered_json report = {{"format", "kincal-calibration-report"}};
  report["project"] = project_record(project, 1);
  EXPECT_EQ(report["project"]["step"], 2);
  EXPECT_EQ(report["project"]["command"], "calibrate");
  const Project again = project_from_report(report, "R.json");
  EXPECT_EQ(again.sha256, project.sha256);
  EXPECT_EQ(project_step_arguments(again.steps[1]), project_step_arguments(project.steps[1]));
  report["project"]["content"] = std::string(kProject) + "# edited\n";
  try {
    project_from_report(report, "R.json");
    FAIL() << "an edited record was accepted";
  } catch (const ProjectError& e) {
    EXPECT_EQ(std::string(e.what()),
              "R.json: project.content does not match its project.sha256 (the report was "
              "edited)");
  }
  EXPECT_THROW(project_from_report(nlohmann::ordered_json::object(), "R.json"), ProjectError);
}

}  // namespace
}  // namespace kincal
