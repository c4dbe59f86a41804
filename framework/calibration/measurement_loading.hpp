#pragma once
// Measurements read for a model and screened, ready to solve: the library's one entry from a
// measurement file to the rows a calibration, a validation or a design uses. It reads the file
// (measurement_file.hpp), refuses data in the wrong unit (data_checks.hpp), screens the rows
// forward kinematics cannot reach at the given parameter values, drops readings a sensor
// cannot take, and counts rows that copy another once. Nothing is printed: what a user should
// read comes back as notes, in order, and a refusal is a std::invalid_argument whose message
// names the file and line.

#include <string>
#include <vector>

#include "kincal/framework/calibration/measurement_file.hpp"

namespace kincal {

struct MeasurementLoadOptions {
  /// Drop the rows forward kinematics cannot reach (each named in a note) instead of refusing
  /// the file.
  bool skip_unreachable_rows = false;
  /// The model's file, named when no row at all is reachable (its values are then as likely
  /// to be wrong as the data); may be empty.
  std::string model_file;
  CsvLimits limits;
};

struct LoadedMeasurements {
  Measurements data;
  std::vector<int> lines;          ///< file line of each kept row
  std::vector<int> skipped_lines;  ///< lines dropped as unreachable
  /// Readings a sensor cannot take at the model's values (Sensor::reads_at), dropped from
  /// rows that other readings keep: "line 12: laser: beam misses the plane".
  std::vector<std::string> dropped_readings;
  /// Rows that copied an earlier row exactly, dropped (find_repeats), and configurations
  /// measured more than once with different readings (kept).
  int duplicate_rows = 0;
  int repeated_configurations = 0;
  int repeat_rows = 0;
  /// What the reader and the screening said, in order ("D.csv:1: ignoring column 't'",
  /// "D.csv:7: skipped, forward kinematics ..."), for the caller to show.
  std::vector<std::string> notes;
  /// The note naming the copied rows, empty when none: kept apart so that a caller can show
  /// it once its own checks of the data passed.
  std::string copied_rows_note;
};

/// Reads `path` for `model` (unit suffixes converted) and screens it at `params` (see the
/// file's comment). Throws std::invalid_argument, with the file and line, when the file
/// cannot be read, its values look like the wrong unit, forward kinematics fails at some
/// rows (unless options.skip_unreachable_rows) or at every row, or no row is left.
LoadedMeasurements load_measurements(const std::string& path, const MeasurementModel& model,
                                     const VectorXd& params,
                                     const MeasurementLoadOptions& options = {});

/// Rows already in memory (a program's own, Python's arrays) as a table whose "lines" are the
/// rows' positions from 1, for screen_measurements.
MeasurementTable table_in_memory(Measurements data);

/// The screening of load_measurements on a table already read: `source` names it in notes
/// and errors ("<source>:<line>: skipped, ..."), as the file's path does. options.limits is
/// not used (the rows are read).
LoadedMeasurements screen_measurements(MeasurementTable table, const MeasurementModel& model,
                                       const VectorXd& params,
                                       const MeasurementLoadOptions& options,
                                       const std::string& source);

}  // namespace kincal
