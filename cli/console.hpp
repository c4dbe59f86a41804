#pragma once
// Where a command prints: out() and err(), its standard output and standard error. The
// program prints on the process's (std::cout, std::cerr); a caller that runs commands
// in-process may give a command streams of its own with a ConsoleScope, so that what the
// command prints is captured and what other threads print meanwhile is not mixed into it
// (the Python module did; it now calls the library and runs no command). Commands print
// through these only, never through printf or std::cout directly.

#include <ostream>
#include <string>

#include "kincal/framework/base/format_text.hpp"
#include "kincal/framework/io/standard_output.hpp"

namespace kincal::cli {

/// The command's standard output: std::cout, or the stream of the ConsoleScope in force.
std::ostream& out();
/// The command's standard error: std::cerr, or the stream of the ConsoleScope in force.
std::ostream& err();
/// Whether out() is the process's standard output (descriptor 1), which then may be a file
/// the command also names (output_plan.hpp compares them).
bool out_is_process_stdout();
/// Whether err() is the process's standard error (then a terminal there shows progress).
bool err_is_process_stderr();

/// out() as the output writers take it (framework/io/output_plan.hpp): what a command printed
/// is flushed before its files are replaced, and its "-" outputs go there. Follows out()
/// (looked up on each use), so it is the same object for every command.
const StandardOutput& console_output();

/// Points out() and err() at `out` and `err` while it lives, for every thread (a command's
/// workers print progress): one at a time in a process, held by whoever runs the command.
class ConsoleScope {
 public:
  ConsoleScope(std::ostream& out, std::ostream& err);
  ~ConsoleScope();
  ConsoleScope(const ConsoleScope&) = delete;
  ConsoleScope& operator=(const ConsoleScope&) = delete;

 private:
  std::ostream* saved_out_;
  std::ostream* saved_err_;
};

}  // namespace kincal::cli
