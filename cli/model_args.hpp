#pragma once
// Helpers shared by the commands that work on model and measurement files (model, fk, ik,
// calibrate, observability, simulate --model).

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "kincal/cli/cli_util.hpp"
#include "kincal/framework/calibration/calibration_problem.hpp"
#include "kincal/framework/calibration/measurement_file.hpp"
#include "kincal/framework/calibration/measurement_loading.hpp"

namespace kincal::cli {

/// --free PATTERN and --fix PATTERN (both repeatable).
void add_free_fix_options(po::options_description& options);
/// Applies every --free pattern, then every --fix pattern; a pattern matching nothing is
/// an error naming the option and the pattern.
void apply_free_fix(const po::variables_map& vm, MeasurementModel& model);

/// The model file of --model (load_model with its errors), checked to be usable: inverse
/// and forward kinematics at its home pose and its predicted readings there must be finite
/// (values such as 1e200 are numbers, but nothing can be computed with them), so that such
/// a file is blamed, not the data read with it.
std::shared_ptr<MeasurementModel> load_model_option(const po::variables_map& vm);
/// The same for a model file named by another option (compare --truth, simulate --truth).
std::shared_ptr<MeasurementModel> load_model_file(const std::string& path);

/// "a,b,c" -> exactly `count` finite numbers; throws CliError naming `option` (its name, with
/// or without the dashes: option_flag) otherwise.
std::vector<double> parse_numbers(const std::string& text, int count, const std::string& option,
                                  const std::string& expected);

/// One "kincal <command>: note: ..." line on stderr.
void note(const std::string& command, const std::string& text);

/// --max-data-size SIZE (bytes, or with KiB, MiB, GiB, KB, MB, GB): the largest measurement
/// file the command reads (default 4 GiB).
void add_data_size_option(po::options_description& options);
/// The measurement reader's limits for this run: --max-data-size, and memory for the rows
/// read, half of what this process may still use (available_memory_bytes()), so that a file
/// too large for the machine stops at the line where it would not fit.
CsvLimits data_limits(const po::variables_map& vm);

/// A measurement reader's error for the command line: the message, and how to raise the
/// file-size limit when that is what stopped it.
CliError measurement_file_error(const std::invalid_argument& e);

/// Measurements read for a model and screened (framework/calibration/measurement_loading.hpp).
using LoadedData = LoadedMeasurements;

/// Prints `loaded.copied_rows_note` as a note of `command`, when there is one.
void note_copied_rows(const std::string& command, const LoadedData& loaded);
/// kincal::load_measurements for a command: its notes printed as "kincal <command>: note:"
/// lines once the file is accepted (a refused file gets one line, the refusal, as a CliError
/// with measurement_file_error's hint); the copied rows' note is left to note_copied_rows.
/// `skip_bad_rows` is --skip-bad-rows.
LoadedData load_measurements(const std::string& command, const std::string& path,
                             const MeasurementModel& model, const VectorXd& params,
                             bool skip_bad_rows, const std::string& model_file,
                             const CsvLimits& limits);

}  // namespace kincal::cli
