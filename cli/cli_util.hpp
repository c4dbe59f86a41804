#pragma once
// Helpers shared by the sub-commands: option parsing, atomic file output, JSON.

#include <boost/program_options.hpp>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "kincal/cli/commands.hpp"
#include "kincal/framework/solver.hpp"

namespace kincal::cli {

namespace po = boost::program_options;

/// Parses `args` against `options`; throws CliError with boost's message on bad input and
/// rejects stray positional arguments. Returns false (after printing help) for --help.
bool parse_command_line(const std::string& command, const Args& args,
                        po::options_description& options, po::variables_map& vm);

/// A random seed on the command line: a whole number >= 0. Boost's own unsigned parsing
/// would turn "-1" into 18446744073709551615 without a word.
struct Seed {
  std::uint64_t value = 1;
};
void validate(boost::any& out, const std::vector<std::string>& values, Seed*, int);

/// "key=value" strings -> map; throws CliError naming the bad entry.
std::map<std::string, std::string> parse_key_values(const std::vector<std::string>& entries,
                                                    const std::string& option_name);

/// Where an output path really leads. Symbolic links are followed, so a link to a file
/// writes that file and stays a link.
struct OutputTarget {
  enum class Kind {
    kStdout,  ///< "-"
    kFile,    ///< a regular file, existing or new: replaced through a temporary file
    kStream,  ///< a character device or FIFO (/dev/null, a terminal, a pipe, /dev/stdout
              ///< and other /proc/self/fd links): written directly, it cannot be replaced
  };
  Kind kind = Kind::kFile;
  std::string path;             ///< as given, for messages
  std::string real;             ///< symbolic links resolved (the directory made absolute)
  bool exists = false;          ///< kFile: the file is there already
  unsigned permissions = 0666;  ///< kFile: mode bits of the existing file
};

/// Resolves `path`. Throws CliError "<what>: <reason>" when it names a directory, another
/// kind of special file (block device, socket), a missing directory, or a symlink loop;
/// `what` names the path in the message (e.g. "--out 'C.json'" or "cannot write 'C.json'").
OutputTarget resolve_output(const std::string& path, const std::string& what);

/// One file to write.
struct OutputFile {
  std::string path;
  std::string content;
};

/// Writes every file or none: each regular file goes to a temporary file beside its real
/// target (same directory, so the rename is atomic), is flushed to disk and takes over the
/// old file's permission bits; only when all of them are written are they renamed over
/// their targets. A failure removes the temporary files and leaves every existing file as
/// it was. Streams (kStream, "-" for stdout) are written after the renames. Throws CliError
/// "cannot write '<path>': <reason>".
void write_files_atomically(const std::vector<OutputFile>& files);

/// write_files_atomically for one file.
void write_file_atomically(const std::string& path, const std::string& content);

/// "lm" when that backend is built, else "gn".
std::string default_solver_name();

/// Adds the options every solving command shares: --solver, --solver-option (repeatable
/// key=value), --max-iterations, --verbose.
void add_solver_options(po::options_description& options);

/// The solver chosen by those options, with its SolverOptions; validates the solver name
/// and backend options up front (throws CliError with the backend's message).
struct SolverChoice {
  std::string name;
  std::unique_ptr<Solver> solver;
  SolverOptions options;
};
SolverChoice make_solver_choice(const po::variables_map& vm);

/// Creates directory `dir` (and parents); throws CliError when that fails.
void ensure_directory(const std::string& dir);

}  // namespace kincal::cli
