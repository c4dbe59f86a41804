#pragma once
// Measurement files: CSV with a header row naming the columns, one row per configuration.
// The actuator columns carry the mechanism's actuator names (leg1..leg6), the reading
// columns the sensors' reading names (gauge). Column order is free; other columns are
// ignored with a notice; blank lines and lines starting with '#' are skipped. Fields are
// plain numbers separated by commas (no quoting); surrounding spaces are ignored. A header
// without a comma but with ';' or tabs (not both) sets that separator instead, with a
// notice; a comma in a field of such a file is a decimal comma, an error (never misread). An empty
// reading field is a reading the sensor did not take (NaN in Measurements): it contributes
// no residual. A sensor's readings in one row are all given or all empty, group by group
// (Sensor::reading_group_size: a camera's u and v of each point), and each a value the sensor
// can read (Sensor::valid_reading: a pixel inside the image). A UTF-8 byte
// order mark at the start is skipped. Lines and files have size limits (CsvLimits).
// A column may carry a unit suffix after its name: <name>_deg, <name>_rad, <name>_mm or
// <name>_m (shoulder_pan_joint_deg); convert_column_units converts such a column into the
// actuator's or reading's own unit. Without a suffix the values are in that unit already.

#include <cstddef>
#include <istream>
#include <map>
#include <string>
#include <vector>

#include "kincal/framework/calibration/calibration_problem.hpp"
#include "kincal/framework/kinematics/measurement_model.hpp"

namespace kincal {

/// Bounds on what is read, so that a wrong file (/dev/zero, a binary) fails fast with a
/// message instead of filling memory. The file limit is far above what kincal writes and
/// instruments log (a tracker at 1 kHz for an hour is about 0.5 GiB); what really bounds a
/// file is memory, which the command line sets from the machine (cli/model_args.hpp).
struct CsvLimits {
  std::size_t max_line_bytes = std::size_t{64} << 10;  ///< 64 KiB, line break not counted
  std::size_t max_file_bytes = std::size_t{4} << 30;   ///< 4 GiB
  /// Memory the rows read may take (table_bytes_per_row each); reading stops with a message
  /// naming the line where they would take more.
  std::size_t max_table_bytes = static_cast<std::size_t>(-1);
};

/// Memory one row of `values` numbers takes while a measurement file is read and after.
inline std::size_t table_bytes_per_row(std::size_t values) { return 16 * values + 64; }

struct MeasurementTable {
  Measurements data;
  /// 1-based line number of each data row in the file, for error messages and reports.
  std::vector<int> line_numbers;
  /// Non-fatal remarks, e.g. "D.csv:1: ignoring column 'temperature'".
  std::vector<std::string> notices;
  /// Per wanted column (actuators, then readings): the unit suffix its header carried
  /// ("deg", "rad", "mm", "m"), or "" when the header gave the bare name.
  std::vector<std::string> column_units;
  int header_line = 0;  ///< 1-based line of the header row
  /// Per wanted column: the header as written (e.g. "joint1_deg"), for messages.
  std::vector<std::string> column_headers;
};

/// The unit suffixes a column name may carry, in the order they are tried.
std::vector<std::string> column_unit_suffixes();

/// Converts every column read with a unit suffix into the unit of its actuator or reading
/// (`actuator_units` then `reading_units`, "mm" or "rad"; "" for a plain number, which takes
/// no suffix): deg -> rad, m -> mm. Throws
/// std::invalid_argument "<source>:<line>: ..." when a suffix is not a unit of that quantity
/// (an angle in mm). Values are replaced in place; NaN (missing) stays NaN.
void convert_column_units(MeasurementTable& table, const std::vector<std::string>& actuator_units,
                          const std::vector<std::string>& reading_units, const std::string& source);

/// Reads `path`. Throws std::invalid_argument with "<path>:<line>: <what was expected>" for a
/// missing file or a directory, a missing or duplicated column, a row with the wrong number of
/// fields, an empty actuator value, a non-numeric, NaN or infinite value or one beyond the
/// range of a double, a NUL byte, a line or a file beyond `limits`, a read error, or a file
/// without data rows.
MeasurementTable read_measurements(const std::string& path,
                                   const std::vector<std::string>& actuator_names,
                                   const std::vector<std::string>& reading_names,
                                   const CsvLimits& limits = {});

/// The header row of a measurement file (the first line that is not blank or a comment), split
/// into its trimmed fields; `line` 0 and no fields when the file has none.
struct CsvHeader {
  std::vector<std::string> fields;
  int line = 0;
};
CsvHeader read_csv_header(const std::string& path, const CsvLimits& limits = {});

/// The text of column `column` (its trimmed field) in each data row of `path` (the rows after
/// the header that are not blank or comments), by the row's 1-based line; empty when the header
/// has no such column, and "" for a row too short to have it. For names beside the numbers:
/// the image each row of `kincal detect` came from. Throws as read_csv_header.
std::map<int, std::string> read_csv_text_column(const std::string& path, const std::string& column,
                                                const CsvLimits& limits = {});
/// The same from a stream; `source` names it in messages.
std::map<int, std::string> parse_csv_text_column(std::istream& in, const std::string& source,
                                                 const std::string& column,
                                                 const CsvLimits& limits = {});

/// read_measurements for `model`'s actuators and readings, then convert_column_units: the
/// configurations of a file whose readings may all be empty (a design template). A sensor's
/// readings may come from the columns of one of its alternative_columns (an orientation as
/// roll-pitch-yaw or a quaternion), converted here; its refused_columns are an error
/// (framework/calibration/model_columns.cpp).
MeasurementTable read_model_columns(const std::string& path, const MeasurementModel& model,
                                    const CsvLimits& limits = {});

/// The configurations of a CSV file: its columns named as `model`'s actuators (other columns
/// ignored, unit suffixes such as _deg converted into each actuator's unit), one row per data
/// line; candidates to choose among, or where the robot was measured (design's
/// --candidates-file and --within). Throws as read_measurements (a file without rows too).
MatrixXd read_configurations(const std::string& path, const MeasurementModel& model,
                             const CsvLimits& limits = {});

/// read_model_columns, then check_sensor_readings: a measurement file to calibrate from.
MeasurementTable read_measurements(const std::string& path, const MeasurementModel& model,
                                   const CsvLimits& limits = {});

/// Throws std::invalid_argument "<source>:<line>: ..." when a row gives some of a group of a
/// sensor's readings but not all, a value the sensor cannot read, or when no reading at all is
/// given; adds a notice for each row without any reading.
void check_sensor_readings(const MeasurementModel& model, MeasurementTable& table,
                           const std::string& source);

/// The same from a stream; `source` names it in messages.
MeasurementTable parse_measurements(std::istream& in, const std::string& source,
                                    const std::vector<std::string>& actuator_names,
                                    const std::vector<std::string>& reading_names,
                                    const CsvLimits& limits = {});

/// Throws std::invalid_argument when `data` under these column names would not read back as
/// it is: a column name the name policy refuses (framework/kinematics/names.hpp, e.g. one
/// holding a ',' or starting with '='), a name given twice, a number of names other than
/// the data's columns, an actuator value that is not finite, an infinite reading (NaN is a
/// reading not taken), or a NUL byte in `comment`. The message names the column or the entry
/// ("actuators[3, 1] ('leg2') is inf").
void check_measurements_writable(const Measurements& data,
                                 const std::vector<std::string>& actuator_names,
                                 const std::vector<std::string>& reading_names,
                                 const std::string& comment = "");

/// CSV text of `data` (header, then one row per configuration, full precision). Each line
/// of `comment` becomes a leading "# " line. Checked first (check_measurements_writable):
/// what is written reads back.
std::string measurements_to_csv(const Measurements& data,
                                const std::vector<std::string>& actuator_names,
                                const std::vector<std::string>& reading_names,
                                const std::string& comment = "");

/// Rows whose readings the model cannot predict at `params` (forward kinematics fails, or
/// no sensor reads any of the row's measured readings), with the reason, in row order. Rows without
/// any reading are not checked: they are not used.
struct UnreachableRow {
  int row = 0;  ///< 0-based row of the Measurements
  std::string reason;
};
std::vector<UnreachableRow> find_unreachable_rows(const MeasurementModel& model,
                                                  const VectorXd& params, const Measurements& data);

/// Measured readings that a sensor cannot take at `params` (Sensor::reads_at: a beam
/// missing its target, a reading out of range) in rows that forward kinematics reaches, one
/// per sensor and row, with the sensor's reason, in row order. A row in which every measured
/// reading is missed is unusable: find_unreachable_rows reports it instead.
struct MissedReading {
  int row = 0;     ///< 0-based row of the Measurements
  int sensor = 0;  ///< index in the model's sensors
  std::string reason;
};
std::vector<MissedReading> find_missed_readings(const MeasurementModel& model,
                                                const VectorXd& params, const Measurements& data);
/// The readings of `missed` set to NaN (not measured), so that they contribute no residual.
void drop_readings(const MeasurementModel& model, const std::vector<MissedReading>& missed,
                   Measurements& data);

/// `data` without the listed 0-based rows (`rows` sorted ascending).
Measurements drop_rows(const Measurements& data, const std::vector<int>& rows);

}  // namespace kincal
