// kincal run PROJECT.yaml: the steps of a project file (framework/io/project_file.hpp), each
// run as its command with the options the file gives it; every step's options are checked
// before the first one runs, and a step that fails stops the run at its line.

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "kincal/cli/cli_util.hpp"
#include "kincal/cli/commands.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/project_record.hpp"
#include "kincal/framework/analysis/calibration_verdict.hpp"
#include "kincal/framework/base/nearest_name.hpp"
#include "kincal/framework/io/json_input.hpp"
#include "kincal/framework/io/output_plan.hpp"
#include "kincal/framework/io/project_file.hpp"

namespace kincal::cli {

namespace {

const Command& find_command(const Project& project, std::size_t index) {
  const std::string& name = project.steps[index].command;
  std::vector<std::string> names;
  for (const Command& command : commands()) {
    if (name == command.name && name != "run") return command;
    if (std::string(command.name) != "run") names.push_back(command.name);
  }
  const std::string near = nearest_name(name, names);
  throw CliError(project_step_location(project, index) + ": '" + name +
                 "' is not a command a project can run" +
                 (near.empty() ? std::string() : " (did you mean '" + near + "'?)") +
                 "; expected one of kincal's commands (kincal --help) other than run");
}

// A command's message about step `index`, at the line of the option it names.
std::string at_step(const Project& project, std::size_t index, const std::string& message) {
  const ProjectStep& step = project.steps[index];
  return project.file + ":" + std::to_string(project_key_line(step, message)) + ": steps[" +
         std::to_string(index + 1) + "]." + step.command + ": " + message;
}

// One argument as a POSIX shell would take it back: bare when plain, else in single quotes
// (a quote inside as '\''), or as $'...' with \xNN escapes when it holds a control character,
// so that the progress line stays one line whatever a project's value holds.
std::string shell_word(const std::string& arg) {
  const bool plain = !arg.empty() && arg.find_first_not_of(
                                         "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                         "0123456789-_./=:,+@%") == std::string::npos;
  if (plain) return arg;
  const bool control = std::any_of(arg.begin(), arg.end(), [](char c) {
    return static_cast<unsigned char>(c) < 0x20 || c == 0x7f;
  });
  std::string word = control ? "$'" : "'";
  for (const char c : arg) {
    if (control && (static_cast<unsigned char>(c) < 0x20 || c == 0x7f || c == '\\' || c == '\'')) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02X", static_cast<unsigned char>(c));
      word += hex;
    } else if (!control && c == '\'') {
      word += "'\\''";
    } else {
      word += c;
    }
  }
  return word + "'";
}

// The step's command line as a shell would take it, for the progress line.
std::string shell_line(const ProjectStep& step) {
  std::string line = "kincal " + step.command;
  for (const std::string& arg : project_step_arguments(step)) line += " " + shell_word(arg);
  return line;
}

// Every step's options parsed, none run: a misspelt key costs nothing.
void check_steps(const Project& project) {
  for (std::size_t i = 0; i < project.steps.size(); ++i) {
    const Command& command = find_command(project, i);
    set_parse_only(true);
    try {
      command.run(project_step_arguments(project.steps[i]));
    } catch (const OptionsChecked&) {
    } catch (const std::exception& e) {
      set_parse_only(false);
      throw CliError(at_step(project, i, e.what()));
    }
    set_parse_only(false);
  }
}

}  // namespace

int run_project(const Args& args) {
  po::options_description options("kincal run PROJECT.yaml");
  options.add_options()("project", po::value<std::string>(),
                        "the project file (YAML or JSON; docs/projects.md); also the first "
                        "word after `run`")(
      "set", po::value<std::vector<std::string>>(),
      "NAME=VALUE: the value of the project's variable NAME (${NAME} in the file), repeatable")(
      "dry-run", po::bool_switch(),
      "check the project and every step's options, print the commands, run nothing")(
      "from-report", po::value<std::string>(),
      "instead of a project file: the project a JSON report records (its content, as it was "
      "run, with its variables; --set still applies), to redo the run")(
      "keep-going", po::bool_switch(),
      "after a step that exits with 1 (a verdict: a check failed, a calibration not to load), "
      "run the later steps too; the exit code is the worst step's");
  Args rest = args;
  std::string project_file;
  if (!rest.empty() && !rest[0].empty() && rest[0][0] != '-') {
    project_file = rest[0];
    rest.erase(rest.begin());
  }
  po::variables_map vm;
  if (!parse_command_line("run", rest, options, vm)) return 0;
  if (vm.count("project")) {
    if (!project_file.empty())
      throw CliError("the project is given twice ('" + project_file + "' and --project)");
    project_file = vm["project"].as<std::string>();
  }
  if (vm.count("from-report") && !project_file.empty())
    throw CliError("give either the project file or --from-report, not both");
  if (project_file.empty() && !vm.count("from-report"))
    throw CliError("expected the project file: kincal run PROJECT.yaml");
  std::vector<std::pair<std::string, std::string>> overrides;
  if (vm.count("set"))
    for (const std::string& item : vm["set"].as<std::vector<std::string>>()) {
      const std::size_t equals = item.find('=');
      if (equals == std::string::npos || equals == 0)
        throw CliError("--set '" + item + "': expected NAME=VALUE");
      overrides.emplace_back(item.substr(0, equals), item.substr(equals + 1));
    }
  const Project project =
      vm.count("from-report")
          ? project_from_report(
                read_json_file(vm["from-report"].as<std::string>(), "report (JSON)"),
                vm["from-report"].as<std::string>(), overrides)
          : read_project(project_file, overrides);
  check_steps(project);
  const std::size_t count = project.steps.size();
  if (vm["dry-run"].as<bool>()) {
    for (std::size_t i = 0; i < count; ++i) out() << shell_line(project.steps[i]) << "\n";
    return 0;
  }
  const bool keep_going = vm["keep-going"].as<bool>();
  int worst = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const ProjectStep& step = project.steps[i];
    const Command& command = find_command(project, i);
    err() << "kincal run: step " << i + 1 << "/" << count << ": " << shell_line(step) << "\n";
    set_active_project_record(project_record(project, i));
    int code = 0;
    try {
      code = command.run(project_step_arguments(step));
    } catch (const std::exception& e) {
      set_active_project_record(std::nullopt);
      throw CliError(at_step(project, i, e.what()));
    }
    set_active_project_record(std::nullopt);
    if (code == 0) continue;
    worst = std::max(worst, code);
    // A verdict (1, or 3 for a calibration not to load) lets --keep-going go on; bad input
    // (2) or an interrupt (130) does not.
    const bool go_on = keep_going && (code == 1 || code == kDoNotLoadExitCode);
    err() << "kincal run: " << project_step_location(project, i) << " exited with " << code
          << (i + 1 == count ? ""
              : go_on        ? "; running the later steps (--keep-going)"
                             : "; the later steps were not run")
          << "\n";
    if (!go_on) return code;
  }
  return worst;
}

}  // namespace kincal::cli
