#pragma once
// Helpers shared by the sub-commands: option parsing, solver choice; files go through
// OutputPlan (framework/io/output_plan.hpp) with console_output() (console.hpp).

#include <boost/program_options.hpp>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "kincal/cli/commands.hpp"
#include "kincal/framework/calibration/calibration_solve.hpp"
#include "kincal/framework/io/output_plan.hpp"
#include "kincal/framework/least_squares/solver.hpp"

namespace kincal::cli {

namespace po = boost::program_options;

/// The entry of a variables_map that parse_command_line fills with every (option, value) in
/// the order given on the command line, a std::vector<std::pair<std::string, std::string>>:
/// boost's map keeps each option's values but not how different options interleave, which
/// decides the outcome of --fix '*' --free 'base.*'.
inline constexpr const char* kOptionOrder = " option order";

/// Parses `args` against `options`; throws CliError with boost's message on bad input and
/// rejects stray positional arguments. Returns false (after printing help or the version) for
/// --help and --version.
bool parse_command_line(const std::string& command, const Args& args,
                        po::options_description& options, po::variables_map& vm);

/// boost's message for `e`, except when an argument holds a "%name%" sequence: boost fills
/// its messages' %placeholders% in a loop that never ends when the text it fills in holds
/// the same placeholder (fuzz_cli_options found `--x%original_token%` hanging the program),
/// so then a message of our own names the option and the argument. An unknown option near a
/// known one of `options` adds "; did you mean --seed?".
std::string option_error_message(const po::error& e, const Args& args,
                                 const po::options_description& options);

/// An old spelling of an option, kept working: `--old_name` parses as `--current_name` (the
/// same value semantic, which the caller passes again) and prints one line on stderr,
/// "kincal <command>: note: --old_name is deprecated: use --current_name (the same option)"
/// once the command has run (deprecation_notes()).
/// Giving both is an error. parse_command_line resolves every alias it finds in `options`,
/// so a command's code reads only the current name.
void add_deprecated_alias(po::options_description& options, const std::string& old_name,
                          const std::string& current_name, const po::value_semantic* semantic);

/// The notes of the aliases used in this run. run() prints them when the command has run and
/// drops them when it stopped on bad input, so that bad input still gets one line.
std::vector<std::string>& deprecation_notes();

/// The current name an option's help text marks it an alias of, or "" when it is none (the
/// option test walks every command's --help with it).
std::string deprecated_alias_target(const std::string& description);

/// A random seed on the command line: a whole number >= 0. Boost's own unsigned parsing
/// would turn "-1" into 18446744073709551615 without a word.
struct Seed {
  std::uint64_t value = 1;
};
void validate(boost::any& out, const std::vector<std::string>& values, Seed*, int);

/// How a message names an option: "--name", whether `name` is given with its dashes or
/// without ("point" and "--point" both give "--point", never "----point").
std::string option_flag(const std::string& name);

/// "key=value" strings -> map; throws CliError naming the bad entry.
std::map<std::string, std::string> parse_key_values(const std::vector<std::string>& entries,
                                                    const std::string& option_name);

/// "lm" when that backend is built, else "gn".
std::string default_solver_name();

/// Adds the options every solving command shares: --solver, --solver-option (repeatable
/// key=value), --max-iterations, --verbose.
void add_solver_options(po::options_description& options);

/// Throws CliError unless a --max-iterations value is at least 1.
void check_max_iterations(int value);

/// The solver chosen by those options, with its SolverOptions; validates the solver name
/// and backend options up front (throws CliError with the backend's message).
struct SolverChoice {
  std::string name;
  std::unique_ptr<Solver> solver;
  SolverOptions options;
};
SolverChoice make_solver_choice(const po::variables_map& vm);

/// --formulation nested|implicit (calibrate, simulate): how the calibration is posed
/// (framework/calibration/calibration_solve.hpp); without it, default_formulation(model).
void add_formulation_option(po::options_description& options);
/// Adds --loss SPEC, a robust loss (calibrate).
void add_loss_option(po::options_description& options);
/// A loss given as --solver-option loss=... is a CliError saying to use --loss (the loss is a
/// setting of every backend, not one backend's own): before make_solver_choice, which would
/// call it an unknown option.
void reject_loss_as_solver_option(const po::variables_map& vm);
/// --loss, parsed and checked against the chosen backend into `choice.options.loss`; a
/// backend that takes no loss is a CliError.
void apply_loss_option(const po::variables_map& vm, SolverChoice& choice);

/// The formulation asked for, or the model's default; throws CliError for another value.
Formulation formulation_choice(const po::variables_map& vm, const MeasurementModel& model);

/// A check asked after every iteration of the solves that make_solver_choice sets up, when
/// one is set: true stops the solve, which then ends user_stopped at the best point so far.
/// The program sets none; the Python module sets one for Ctrl-C (python/src/interrupt.cpp).
/// Empty: no check. Set it before a command runs, not during one.
void set_solver_stop_check(std::function<bool()> check);

}  // namespace kincal::cli
