// kincal's commands run in-process: the same code as the program (cli/run.hpp), so that a
// report's JSON is the program's byte for byte. Python builds the option list (kincal/
// _commands.py); this runs it with the GIL released and its standard output and error
// captured.

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "interrupt.hpp"
#include "kincal/cli/run.hpp"

namespace kincal::python {

namespace {

// Standard output or error sent to a temporary file while it lives, then restored.
class Capture {
 public:
  explicit Capture(int fd) : fd_(fd) {
    std::FILE* file = std::tmpfile();
    if (!file) throw std::runtime_error("kincal: cannot create a temporary file for the output");
    file_ = file;
    flush();
    saved_ = ::dup(fd_);
    ::dup2(::fileno(file_), fd_);
  }
  ~Capture() {
    if (saved_ >= 0) restore();
    std::fclose(file_);
  }
  Capture(const Capture&) = delete;
  Capture& operator=(const Capture&) = delete;
  /// Restores the descriptor and returns what was written.
  std::string restore() {
    flush();
    ::dup2(saved_, fd_);
    ::close(saved_);
    saved_ = -1;
    std::string text;
    std::rewind(file_);
    char buffer[4096];
    std::size_t n;
    while ((n = std::fread(buffer, 1, sizeof buffer, file_)) > 0) text.append(buffer, n);
    return text;
  }

 private:
  static void flush() {
    std::cout.flush();
    std::cerr.flush();
    std::fflush(stdout);
    std::fflush(stderr);
  }
  int fd_;
  std::FILE* file_ = nullptr;
  int saved_ = -1;
};

// The commands share process state (descriptors, the Ctrl-C handler): one at a time.
std::mutex g_command_mutex;

py::tuple run_command(const std::vector<std::string>& args, bool catch_sigint) {
  std::vector<const char*> argv = {"kincal"};
  for (const auto& a : args) argv.push_back(a.c_str());
  int code = 0;
  std::string out, err;
  bool interrupted = false;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(g_command_mutex);
    SigintScope sigint(catch_sigint);
    Capture capture_out(STDOUT_FILENO), capture_err(STDERR_FILENO);
    code = cli::run(static_cast<int>(argv.size()), argv.data());
    err = capture_err.restore();
    out = capture_out.restore();
    interrupted = sigint.interrupted();
  }
  return py::make_tuple(code, py::bytes(out), py::bytes(err), interrupted);
}

}  // namespace

void bind_commands(py::module_& m) {
  m.def("run_command", &run_command, py::arg("args"), py::arg("catch_sigint") = false,
        "Runs `kincal ARGS...` in this process with the GIL released; returns (exit code, "
        "standard output, standard error, interrupted). With catch_sigint (main thread "
        "only), Ctrl-C stops the solves at their best point so far (interrupted = True).");
}

}  // namespace kincal::python
