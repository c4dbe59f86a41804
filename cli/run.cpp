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
#include "kincal/cli/output_files.hpp"
#include "kincal/cli/output_plan.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/extension/plugin.hpp"

namespace kincal::cli {

const std::vector<Command>& commands() {
  static const std::vector<Command> table = {
      {"list", "list solver backends, preset models, mechanism and sensor types", run_list},
      {"simulate", "run one simulated calibration of a preset or a model file", run_simulate},
      {"reproduce", "Monte Carlo of the paper's five Table 2 cases", run_reproduce},
      {"model", "write a built-in model as an editable model file", run_model},
      {"fk", "forward kinematics of a model file: actuator values -> pose", run_fk},
      {"ik", "inverse kinematics of a model file: pose -> actuator values", run_ik},
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
         "--plugin FILE (any command, repeatable) loads a plug-in with further mechanism, sensor\n"
         "and solver types, after those named by KINCAL_PLUGIN_PATH (files or folders, ':'\n"
         "between them).\n\n"
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

// Takes every `--plugin FILE` / `--plugin=FILE` out of `args`: a global option, so that no
// command spells it. Returns the files in the order given.
std::vector<std::string> take_plugin_options(Args& args) {
  std::vector<std::string> files;
  Args rest;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--") {  // the rest are operands
      rest.insert(rest.end(), args.begin() + static_cast<std::ptrdiff_t>(i), args.end());
      break;
    }
    if (args[i] == "--plugin") {
      if (i + 1 == args.size()) throw CliError("--plugin needs a file (a kincal plug-in)");
      files.push_back(args[++i]);
    } else if (args[i].rfind("--plugin=", 0) == 0) {
      files.push_back(args[i].substr(9));
      if (files.back().empty()) throw CliError("--plugin needs a file (a kincal plug-in)");
    } else {
      rest.push_back(args[i]);
    }
  }
  args = std::move(rest);
  return files;
}

// KINCAL_PLUGIN_PATH's plug-ins, then --plugin's, into the global registries.
void load_plugins(Args& args) {
  std::vector<std::string> files = plugins_from_environment();
  const std::vector<std::string> given = take_plugin_options(args);
  files.insert(files.end(), given.begin(), given.end());
  for (const auto& file : files) load_plugin(file);
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
      check_standard_output();
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
      Args args(argv + 2, argv + argc);
      load_plugins(args);
      const int code = command.run(args);
      check_standard_output();  // what was printed after the last file: never lost silently
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
    }
  }
  err() << "kincal: error: unknown command '" << message_excerpt(name) << "' (try kincal --help)\n";
  return 2;
}

}  // namespace kincal::cli
