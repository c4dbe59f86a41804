#pragma once
// The options every command spells the same way, in one place, so that a new command gets
// them right by calling these (docs/architecture.md, "A CLI command"):
//
//   --json FILE|-   the command's result as JSON (add_json_option / json_output), a document
//                   that starts with its format and version (json_document)
//   --progress      progress with time remaining on stderr (add_progress_option; cli/progress.hpp)
//   --version       handled by parse_command_line for every command (version_text)
//   defaults        shown as a person writes them (default_text)

#include <nlohmann/json.hpp>
#include <string>

#include "kincal/cli/cli_util.hpp"

namespace kincal::cli {

/// Adds --json FILE|-: "write <what> as JSON to FILE, or - for standard output".
void add_json_option(po::options_description& options, const std::string& what);

/// The --json path, or "" when not given.
std::string json_output(const po::variables_map& vm);

/// The start of every --json document: {"format": "kincal-<command>", "version": N}, so
/// that a reader can tell what it holds and whether it knows that version (a test checks
/// every command's). A format's version changes when a key changes meaning or goes away.
nlohmann::ordered_json json_document(const std::string& format, int version = 1);

/// Adds --progress: progress with time remaining on stderr even when stderr is not a
/// terminal (it is shown on a terminal anyway).
void add_progress_option(po::options_description& options);

/// Whether to show progress: --progress, or stderr is a terminal. Tests and pipes stay clean.
bool progress_wanted(const po::variables_map& vm);

/// A number as a person writes it in --help: 1e-06, 0.5, 200 (shortest %g form that reads
/// back as the same double), not boost's 9.9999999999999995e-07.
std::string default_text(double value);

/// "kincal 0.1.0 (git v0.1.0-12-gabcdef)\nsolver backends: ..." for --version.
std::string version_text();

}  // namespace kincal::cli
