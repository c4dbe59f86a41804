#pragma once
// Where a caller of the output writers (output_files.hpp, output_plan.hpp) prints: the library
// prints nothing itself, but what a command printed must reach its standard output before any
// file is replaced, and an output named "-" is written there.

#include <ostream>

namespace kincal {

/// Where the caller prints (the program: its out(), cli/console.hpp). What was printed there
/// comes before any file is replaced, and an output named "-" is written there, so that a
/// full disk or a closed stream fails before anything is replaced.
class StandardOutput {
 public:
  virtual ~StandardOutput() = default;
  virtual std::ostream& stream() const = 0;
  /// Whether stream() is the process's standard output (descriptor 1): stdio's stdout is
  /// then flushed with it, and it may be a file that the caller also names (OutputPlan
  /// compares them).
  virtual bool is_process_stdout() const = 0;
};

/// A stream of the caller's, not the process's standard output: the Python module's, which
/// prints nothing (it passes "-" as the file "./-").
class StreamOutput final : public StandardOutput {
 public:
  explicit StreamOutput(std::ostream& stream) : stream_(&stream) {}
  std::ostream& stream() const override { return *stream_; }
  bool is_process_stdout() const override { return false; }

 private:
  std::ostream* stream_;
};

}  // namespace kincal
