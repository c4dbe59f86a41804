#pragma once
// Helpers shared by the commands that work on model and measurement files (model, fk, ik,
// calibrate, observability, simulate --model).

#include <memory>
#include <string>
#include <vector>

#include "kincal/cli/cli_util.hpp"
#include "kincal/framework/calibration_problem.hpp"

namespace kincal::cli {

/// --free PATTERN and --fix PATTERN (both repeatable).
void add_free_fix_options(po::options_description& options);
/// Applies every --free pattern, then every --fix pattern; a pattern matching nothing is
/// an error naming the option and the pattern.
void apply_free_fix(const po::variables_map& vm, MeasurementModel& model);

/// The model file of --model (load_model with its errors).
std::shared_ptr<MeasurementModel> load_model_option(const po::variables_map& vm);

/// "a,b,c" -> exactly `count` finite numbers; throws CliError naming `option` otherwise.
std::vector<double> parse_numbers(const std::string& text, int count, const std::string& option,
                                  const std::string& expected);

/// Throws CliError when `path` (an output of `option`) cannot be created: checked before
/// long work so that a typo in a path does not cost a solve. "-" is always writable.
void check_writable(const std::string& path, const std::string& option);

/// One "kincal <command>: note: ..." line on stderr.
void note(const std::string& command, const std::string& text);

/// Measurements read for a model, with unreachable rows screened.
struct LoadedData {
  Measurements data;
  std::vector<int> lines;          ///< file line of each kept row
  std::vector<int> skipped_lines;  ///< lines dropped as unreachable
};
/// Reads `path` for `model`, then checks that forward kinematics works at `params` for
/// every row: unreachable rows are an error naming their lines, or, with `skip_bad_rows`,
/// dropped with a note.
LoadedData load_measurements(const std::string& command, const std::string& path,
                             const MeasurementModel& model, const VectorXd& params,
                             bool skip_bad_rows);

}  // namespace kincal::cli
