#pragma once
// The one place where a task's files are checked and written, for the program's commands and
// the Python module alike. A caller declares every file it reads and writes, calls check()
// before any work, and writes through write():
//
//   OutputPlan plan(standard_output);      // where the caller prints (output_files.hpp)
//   plan.input("--data", data);            // files read
//   plan.output("--out", out);             // files written ("-" is standard output)
//   plan.check();                          // throws OutputError: collisions, unwritable paths
//   ... work ...
//   plan.write({{"--report", report_text}, {"--out", model_text}});
//
// Rules (docs/reliability.md): no output may be an input or another output. Files are
// compared by what they are, not by how they are named: symbolic links are followed, hard
// links are the same inode (device + inode number), "-", /dev/stdout and /proc/self/fd/1
// are all standard output, and standard output itself, where every command prints, must not
// be an input either (kincal ... >> D.csv). The null device may be named any number of times.
// The labels name the files in messages: the program's options ("--out"), Python's keywords.

#include <string>
#include <utility>
#include <vector>

#include "kincal/framework/io/output_files.hpp"

namespace kincal {

class OutputPlan {
 public:
  /// `standard_output` is where the caller prints, and where "-" outputs go; it must outlive
  /// the plan.
  explicit OutputPlan(const StandardOutput& standard_output) : standard_output_(&standard_output) {}

  /// A file the command reads; `label` names it in messages ("--data").
  void input(const std::string& label, const std::string& path);
  /// A file the command writes, or "-" for standard output.
  void output(const std::string& label, const std::string& path);
  /// A directory the command replaces whole, holding only the files named `files`.
  void output_directory(const std::string& label, const std::string& path,
                        const std::vector<std::string>& files);

  /// Resolves every path and throws OutputError when an output is an input or another
  /// output, or cannot be written (missing directory, a directory given as a file, a
  /// read-only directory). Call it before any work.
  void check();

  /// True when output `label` is standard output ("-", /dev/stdout, ...): the command then
  /// prints nothing else there.
  bool to_stdout(const std::string& label) const;

  /// Writes the declared outputs given as (label, content), all or none while the process
  /// runs (write_files_atomically), renaming them in the order given: the last one is
  /// replaced last.
  void write(const std::vector<std::pair<std::string, std::string>>& contents) const;

  /// Writes the directory `label` with `files` (name, content), atomically
  /// (write_directory_atomically).
  void write_directory(const std::string& label,
                       const std::vector<std::pair<std::string, std::string>>& files) const;

 private:
  struct Entry {
    std::string label, path;
    bool is_output = false, is_directory = false;
    std::vector<std::string> files;  // a directory's own files
  };
  const Entry& find(const std::string& label, bool directory) const;

  const StandardOutput* standard_output_;
  std::vector<Entry> entries_;
  bool checked_ = false;
};

/// The program's option-parsing fuzzer (fuzz/fuzz_cli_options.cpp) runs commands in-process
/// and must stop them before they do any work: when set, OutputPlan::check() throws
/// OptionsChecked after its checks.
void stop_after_option_checks(bool stop);
struct OptionsChecked {};  ///< deliberately not a std::exception

}  // namespace kincal
