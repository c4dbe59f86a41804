// The command table and dispatch of the kincal program. Thin: parse, call the library,
// print.

#include "kincal/cli/run.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <iostream>
#include <new>

#include "kincal/cli/commands.hpp"
#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/base/nearest_name.hpp"
#include "kincal/framework/extension/plugin.hpp"
#include "kincal/framework/io/output_files.hpp"
#include "kincal/framework/io/output_plan.hpp"

namespace kincal::cli {

const std::vector<Command>& commands() {
  static const std::vector<Command> table = {
      {"list", "list solver backends, preset models, mechanism and sensor types", run_list},
      {"run", "run a project file: a whole calibration as one YAML or JSON file", run_project},
      {"simulate", "run one simulated calibration of a preset or a model file", run_simulate},
      {"reproduce", "Monte Carlo of the paper's five Table 2 cases", run_reproduce},
      {"model", "write a built-in model as an editable model file", run_model},
      {"fk", "forward kinematics of a model file: actuator values -> pose", run_fk},
      {"ik", "inverse kinematics of a model file: pose -> actuator values", run_ik},
      {"compensate",
       "corrected targets: the commands that make a calibrated model read what is wanted",
       run_compensate},
      {"detect", "find a calibration target in images: images -> measurement file (camera)",
       run_detect},
      {"calibrate", "calibrate a model file from a measurement file", run_calibrate},
      {"observability", "which free parameters a set of configurations can determine",
       run_observability},
      {"validate", "residuals of a calibrated model on held-out data against the prediction",
       run_validate},
      {"design", "choose the configurations to measure (experiment design)", run_design},
      {"compare", "a model against a known truth: parameter and pose errors", run_compare},
      {"solver-suite", "backends on the Moré-Garbow-Hillstrom test problems, checked",
       run_solver_suite},
      {"verify", "check that a calibrated model is the one its report was written with",
       run_verify},
      {"export", "a calibrated model as URDF (serial arms), joint-coordinate CSV or JSON",
       run_export},
      {"check", "conformance checks of a preset or model file (e.g. a plug-in's types)", run_check},
  };
  return table;
}

namespace {

void print_usage(std::ostream& out) {
  out << "usage: kincal <command> [options] [--plugin FILE ...]   (kincal <command> --help for "
         "its options)\n"
         "       kincal --version\n\n"
         "--plugin FILE (any command's option, repeatable) loads a plug-in with further\n"
         "mechanism, sensor and solver types, after those named by KINCAL_PLUGIN_PATH (files or\n"
         "folders, ':' between them).\n\n"
         "commands:\n";
  for (const auto& c : commands()) {
    std::string name = c.name;
    name.resize(14, ' ');
    out << "  " << name << c.summary << "\n";
  }
}

// One line whatever the message holds (a path with a line break, a 60 KB field).
void print_error(const std::string& command, const std::string& what) {
  err() << "kincal " << command << ": error: " << message_excerpt(what, 4000) << "\n";
}

// What to say about an exception that is not a std::exception: kincal throws none, so one
// came from a plug-in's code (a method of one of its types, called during the run;
// registration and factories are guarded by name in framework/extension/plugin.cpp).
std::string unknown_exception_text() {
  std::string list;
  for (const std::string& file : loaded_plugins())
    list += (list.empty() ? "'" : "', '") + printable(file);
  if (list.empty()) return "an exception that is not a std::exception (a bug: please report it)";
  return "a plug-in threw an exception that is not a std::exception (loaded: " + list +
         "'); a plug-in must throw std::exception or a class derived from it";
}

}  // namespace

void prepare_process() {
  for (int fd = STDIN_FILENO; fd <= STDERR_FILENO; ++fd)
    if (::fcntl(fd, F_GETFD) < 0 && errno == EBADF) {
      const int opened = ::open("/dev/null", O_RDONLY);
      if (opened >= 0 && opened != fd) {
        ::dup2(opened, fd);
        ::close(opened);
      }
    }
  std::signal(SIGXFSZ, SIG_IGN);
}

int run(int argc, const char* const* argv) {
  if (argc < 2) {
    print_usage(err());
    return 2;
  }
  const std::string name = argv[1];
  if (name == "--help" || name == "-h" || name == "help" || name == "--version" ||
      name == "version") {
    if (name.find("version") != std::string::npos)
      out() << version_text();
    else
      print_usage(out());
    try {
      check_standard_output(console_output());
    } catch (const std::exception& e) {
      print_error(name, e.what());
      return 2;
    }
    return 0;
  }
  for (const auto& command : commands()) {
    if (name != command.name) continue;
    deprecation_notes().clear();
    try {
      // The plug-ins are loaded by parse_command_line, once the options have been parsed
      // (cli/plugin_option.hpp): never from a token that is another option's value.
      const Args args(argv + 2, argv + argc);
      const int code = command.run(args);
      // What was printed after the last file: never lost silently.
      check_standard_output(console_output());
      for (const std::string& line : deprecation_notes()) err() << line << "\n";
      return code;
    } catch (const OptionsChecked&) {
      return 0;  // the fuzzer's stop before any work (stop_after_option_checks)
    } catch (const std::bad_alloc&) {
      print_error(name, "out of memory");
      return 2;
    } catch (const std::exception& e) {
      print_error(name, e.what());
      return 2;
    } catch (...) {
      print_error(name, unknown_exception_text());  // one line rather than std::terminate
      return 2;
    }
  }
  std::vector<std::string> names;
  for (const auto& command : commands()) names.push_back(command.name);
  const std::string near = nearest_name(name, names);
  err() << "kincal: error: unknown command '" << message_excerpt(name) << "'"
        << (near.empty() ? std::string() : "; did you mean '" + near + "'?")
        << " (try kincal --help)\n";
  return 2;
}

}  // namespace kincal::cli
