#pragma once
// A project file: a whole calibration (model, data, parameters, solver, validation, outputs)
// in one file instead of a shell history, run by `kincal run PROJECT.yaml` and Python's
// kincal.run_project (docs/projects.md). YAML, or JSON with the same keys:
//
//   name: UR5 with a laser tracker        # optional, for people
//   variables: {out: results}             # ${out} in any value; `--set out=DIR` replaces it
//   steps:                                # run in order, one command each
//     - model: {urdf: ur5.urdf, tip: flange, sensor: point-tracker, out: ${out}/ur5.json}
//     - calibrate: {model: ${out}/ur5.json, data: grid.csv, free: [base.*, tool.x]}
//
// A step's keys are its command's options without the leading dashes (an underscore may
// stand for a dash: Python's spelling); a list repeats the option in its order, `true` is a
// switch given and `false` one left out, a map gives KEY=VALUE items (solver-option). Every
// command-line option therefore has its key, by construction. Paths (project_path_option)
// are relative to the project file's folder, so the project runs the same from anywhere.
//
// Errors are one line naming the file, the line and the key: "p.yaml:12: steps[1].calibrate:
// ...". The reader checks the file's shape; the options themselves are checked by the
// command that takes them (the faces map its message to the key's line: project_key_line).

#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace kincal {

/// A project file that cannot be read or has the wrong shape; what() is one line starting
/// with "<file>:<line>: ".
class ProjectError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

struct ProjectOption {
  /// The option's name with dashes ("skip-bad-rows"), as the command line spells it.
  std::string key;
  /// Its values in order, variables substituted and paths resolved; empty for a switch.
  std::vector<std::string> values;
  bool is_switch = false;
  /// 1-based line of the key in the project file.
  int line = 0;
};

struct ProjectStep {
  /// The command ("calibrate"), as `kincal <command>` names it.
  std::string command;
  int line = 0;
  std::vector<ProjectOption> options;
};

struct Project {
  /// The file as given, and its folder made absolute (what relative paths start from).
  std::string file;
  std::string folder;
  /// The file's bytes and their SHA-256: what a report records so the run can be redone.
  std::string content;
  std::string sha256;
  std::string name;
  /// The variables' values after `--set` (sorted by name).
  std::map<std::string, std::string> variables;
  std::vector<ProjectStep> steps;
};

/// Reads and checks the project file `path`; `overrides` (NAME, VALUE) replace the values of
/// variables the file declares (a name it does not declare is an error). At most 1 MiB.
Project read_project(const std::string& path,
                     const std::vector<std::pair<std::string, std::string>>& overrides = {});

/// The same from the file's text (`path` names it in messages and gives the folder).
Project parse_project(const std::string& text, const std::string& path,
                      const std::vector<std::pair<std::string, std::string>>& overrides = {});

/// Whether option `key` of `command` names a file or folder (resolved against the project's
/// folder): model, data, out, json, html, report, ... for every command; poses for detect and
/// ik (elsewhere a count).
bool project_path_option(const std::string& command, const std::string& key);

/// The step as command-line arguments after the command's name: "--key", "value", ...
std::vector<std::string> project_step_arguments(const ProjectStep& step);

/// "<file>:<line>: steps[i].<command>" (i 1-based), for messages about step `index`.
std::string project_step_location(const Project& project, std::size_t index);

/// The line of the option a command's message is about: the first option of the step whose
/// "--key" the message names, else the first whose value (a path, 3 characters or more) it
/// names; the step's own line when none.
int project_key_line(const ProjectStep& step, const std::string& message);

/// What a report records of the project it was run from: {file, sha256, step, command,
/// variables, content}, so that `kincal run` on the content redoes the run.
nlohmann::ordered_json project_record(const Project& project, std::size_t step_index);

/// The project a report (`source` names it in messages) records, as it was run: its recorded
/// content (checked against its SHA-256) read as if it were at its recorded file, with its
/// recorded variables, then `overrides`.
Project project_from_report(const nlohmann::ordered_json& report, const std::string& source,
                            const std::vector<std::pair<std::string, std::string>>& overrides = {});

}  // namespace kincal
