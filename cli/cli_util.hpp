#pragma once
// Helpers shared by the sub-commands: option parsing, atomic file output, JSON.

#include <boost/program_options.hpp>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "framework/solver.hpp"

namespace kincal::cli {

namespace po = boost::program_options;

/// Parses `args` against `options`; throws CliError with boost's message on bad input and
/// rejects stray positional arguments. Returns false (after printing help) for --help.
bool parse_command_line(const std::string& command, const Args& args,
                        po::options_description& options, po::variables_map& vm);

/// "key=value" strings -> map; throws CliError naming the bad entry.
std::map<std::string, std::string> parse_key_values(const std::vector<std::string>& entries,
                                                    const std::string& option_name);

/// Writes `content` to `path` through a temporary file in the same directory and a rename,
/// so an existing file is never left half-written. "-" writes to stdout. Throws CliError
/// naming the path when it cannot be written.
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
