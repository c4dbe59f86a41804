#pragma once
// Helpers shared by the sub-commands: option parsing, atomic file output, JSON.

#include <boost/program_options.hpp>
#include <map>
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

/// Creates directory `dir` (and parents); throws CliError when that fails.
void ensure_directory(const std::string& dir);

}  // namespace kincal::cli
