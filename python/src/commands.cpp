// kincal's commands run in-process: the same code as the program (cli/run.hpp), so that a
// report's JSON is the program's byte for byte. Python builds the option list (kincal/
// _commands.py); this runs it with the GIL released and gives it standard output and error
// of its own (cli/console.hpp): what the command prints is returned, and what other threads
// print meanwhile goes where it always goes, not into the command's text.

#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "interrupt.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/run.hpp"

namespace kincal::python {

namespace {

py::tuple run_command(const std::vector<std::string>& args, bool catch_sigint) {
  std::vector<const char*> argv = {"kincal"};
  for (const auto& a : args) argv.push_back(a.c_str());
  int code = 0;
  std::ostringstream out, err;
  bool interrupted = false;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(command_mutex());
    SigintScope sigint(catch_sigint);
    const cli::ConsoleScope console(out, err);
    code = cli::run(static_cast<int>(argv.size()), argv.data());
    interrupted = sigint.interrupted();
  }
  return py::make_tuple(code, py::bytes(out.str()), py::bytes(err.str()), interrupted);
}

}  // namespace

std::mutex& command_mutex() {
  static std::mutex mutex;
  return mutex;
}

void bind_commands(py::module_& m) {
  m.def("run_command", &run_command, py::arg("args"), py::arg("catch_sigint") = false,
        "Runs `kincal ARGS...` in this process with the GIL released; returns (exit code, "
        "standard output, standard error, interrupted). With catch_sigint (main thread "
        "only), Ctrl-C stops the solves at their best point so far (interrupted = True).");
}

}  // namespace kincal::python
