#include "kincal/framework/calibration/measurement_file.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/base/parallel.hpp"
#include "kincal/framework/kinematics/names.hpp"

namespace kincal {

namespace {

// The fields of `line`, trimmed, into `fields` (whose storage is reused from line to line).
void split_fields(const std::string& line, char separator, std::vector<std::string>& fields) {
  fields.clear();
  std::string::size_type start = 0;
  while (true) {
    const auto comma = line.find(separator, start);
    const auto end = comma == std::string::npos ? line.size() : comma;
    auto first = start, last = end;
    while (first < last && (line[first] == ' ' || line[first] == '\t' || line[first] == '\r'))
      ++first;
    while (last > first &&
           (line[last - 1] == ' ' || line[last - 1] == '\t' || line[last - 1] == '\r'))
      --last;
    fields.emplace_back(line, first, last - first);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
}

std::vector<std::string> split_fields(const std::string& line, char separator = ',') {
  std::vector<std::string> fields;
  split_fields(line, separator, fields);
  return fields;
}

const char* separator_name(char separator) {
  return separator == ';' ? "';' (semicolons)" : separator == '\t' ? "tabs" : "','";
}

// The field separator, from the header: ',' as documented, or, when the header has no comma,
// ';' or a tab if exactly one of them appears (spreadsheets in locales whose decimal mark is
// a comma save CSV with ';'; "text" exports use tabs). Throws when the header does not tell.
char detect_separator(const std::string& header, const std::string& at) {
  if (header.find(',') != std::string::npos) return ',';
  const bool semicolon = header.find(';') != std::string::npos;
  const bool tab = header.find('\t') != std::string::npos;
  if (semicolon && tab)
    throw std::invalid_argument(at +
                                ": the header has no comma but both ';' and tabs, so the field "
                                "separator is ambiguous; expected fields separated by commas");
  return semicolon ? ';' : tab ? '\t' : ',';
}

// A blank line or a comment ('#' after any blanks): skipped. Tested in place, without a copy.
bool is_skipped(const std::string& line) {
  const auto first = line.find_first_not_of(" \t\r");
  return first == std::string::npos || line[first] == '#';
}

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ",") + n;
  return out;
}

// strtod accepts "nan" and "inf", and stops at the first bad character (an embedded NUL
// included): check both. Underflow (1e-400) rounds to zero or a subnormal number, as any
// decimal rounds to the nearest double; overflow (1e999) has no double to round to.
// `where()` says where the field is, for a message: called only when there is one.
template <typename Where>
double parse_value(const std::string& field, const Where& where) {
  if (field.empty()) throw std::invalid_argument(where() + " is empty, expected a number");
  const char* begin = field.c_str();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  if (end != begin + field.size())
    throw std::invalid_argument(where() + ": '" + message_excerpt(field) + "' is not a number");
  if (!std::isfinite(v) && errno != ERANGE)
    throw std::invalid_argument(where() + ": '" + message_excerpt(field) +
                                "' is not a finite number");
  if (!std::isfinite(v))
    throw std::invalid_argument(where() + ": '" + message_excerpt(field) +
                                "' is beyond the range of a double (magnitude above 1.8e308)");
  return v;
}

// Lines of the file within `limits`. A line longer than the limit, a file larger than it
// or a NUL byte (a binary file, /dev/zero) stops with a message naming the line, after
// reading at most one line past what is allowed.
class LineReader {
 public:
  LineReader(std::istream& in, const std::string& source, const CsvLimits& limits)
      : in_(in), source_(source), limits_(limits), buffer_(limits.max_line_bytes + 1) {}

  // The next line without its line break; false at the end of the input or at a read error.
  bool next(std::string& line) {
    if (!in_) return false;
    in_.getline(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    const auto count = static_cast<std::size_t>(in_.gcount());
    if (count == 0 && in_.eof()) return false;
    if (in_.bad()) return false;
    ++line_number_;
    const bool too_long = in_.fail() && !in_.eof();  // getline stopped at the buffer's end
    const std::size_t stored = too_long || in_.eof() ? count : count - 1;
    const std::string at = source_ + ":" + std::to_string(line_number_);
    if (const void* nul = std::memchr(buffer_.data(), '\0', stored))
      throw std::invalid_argument(
          at + ": NUL byte at column " +
          std::to_string(static_cast<const char*>(nul) - buffer_.data() + 1) +
          "; expected a text file (CSV)");
    if (too_long)
      throw std::invalid_argument(at + ": line longer than the limit of " +
                                  std::to_string(limits_.max_line_bytes) +
                                  " bytes; expected a measurement file (CSV)");
    bytes_ += count;
    if (bytes_ > limits_.max_file_bytes)
      throw std::invalid_argument(
          source_ + ": larger than the limit of " + std::to_string(limits_.max_file_bytes >> 20) +
          " MiB (" + std::to_string(limits_.max_file_bytes) + " bytes) for a measurement file");
    line.assign(buffer_.data(), stored);
    // Spreadsheets save "CSV UTF-8" with a byte order mark, which would join the first name.
    if (line_number_ == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
    return true;
  }

  int line_number() const { return line_number_; }

 private:
  std::istream& in_;
  const std::string& source_;
  CsvLimits limits_;
  std::vector<char> buffer_;
  int line_number_ = 0;
  std::size_t bytes_ = 0;
};

// Rows per chunk of the per-row forward kinematics passes, which run in parallel.
constexpr int kRowsPerChunk = 4096;

}  // namespace

namespace {

// The file at `path` opened for reading, or std::invalid_argument naming what it is. An
// ifstream opens a directory and then reads nothing, which would read as "no header".
std::ifstream open_measurement_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw std::invalid_argument(path + ": is a directory, expected a measurement file (CSV)");
  std::ifstream in(path);
  if (!in)
    throw std::invalid_argument(path + ": cannot open measurement file (missing or unreadable)");
  return in;
}

}  // namespace

MeasurementTable read_measurements(const std::string& path,
                                   const std::vector<std::string>& actuator_names,
                                   const std::vector<std::string>& reading_names,
                                   const CsvLimits& limits) {
  std::ifstream in = open_measurement_file(path);
  try {
    return parse_measurements(in, path, actuator_names, reading_names, limits);
  } catch (const std::ios_base::failure& e) {
    throw std::invalid_argument(path + ": cannot read measurement file (" + e.what() + ")");
  }
}

CsvHeader read_csv_header(const std::string& path, const CsvLimits& limits) {
  std::ifstream in = open_measurement_file(path);
  CsvHeader header;
  try {
    LineReader reader(in, path, limits);
    std::string line;
    while (reader.next(line)) {
      if (is_skipped(line)) continue;
      header.line = reader.line_number();
      header.fields =
          split_fields(line, detect_separator(line, path + ":" + std::to_string(header.line)));
      break;
    }
  } catch (const std::ios_base::failure& e) {
    throw std::invalid_argument(path + ": cannot read measurement file (" + e.what() + ")");
  }
  return header;
}

std::map<int, std::string> parse_csv_text_column(std::istream& in, const std::string& source,
                                                 const std::string& column,
                                                 const CsvLimits& limits) {
  std::map<int, std::string> out;
  try {
    LineReader reader(in, source, limits);
    std::string line;
    char separator = ',';
    int index = -1;
    bool header = true;
    std::vector<std::string> fields;
    while (reader.next(line)) {
      if (is_skipped(line)) continue;
      if (header) {
        header = false;
        separator = detect_separator(line, source + ":" + std::to_string(reader.line_number()));
        split_fields(line, separator, fields);
        for (std::size_t c = 0; c < fields.size() && index < 0; ++c)
          if (fields[c] == column) index = static_cast<int>(c);
        if (index < 0) return out;
        continue;
      }
      split_fields(line, separator, fields);
      out[reader.line_number()] = index < static_cast<int>(fields.size()) ? fields[index] : "";
    }
  } catch (const std::ios_base::failure& e) {
    throw std::invalid_argument(source + ": cannot read measurement file (" + e.what() + ")");
  }
  return out;
}

std::map<int, std::string> read_csv_text_column(const std::string& path, const std::string& column,
                                                const CsvLimits& limits) {
  std::ifstream in = open_measurement_file(path);
  return parse_csv_text_column(in, path, column, limits);
}

MeasurementTable parse_measurements(std::istream& in, const std::string& source,
                                    const std::vector<std::string>& actuator_names,
                                    const std::vector<std::string>& reading_names,
                                    const CsvLimits& limits) {
  MeasurementTable table;
  std::vector<std::string> wanted = actuator_names;
  wanted.insert(wanted.end(), reading_names.begin(), reading_names.end());
  const std::string expected = "expected columns " + join(wanted);

  LineReader reader(in, source, limits);
  std::string line;
  std::vector<std::string> header;
  int header_line = 0;
  char separator = ',';
  while (reader.next(line)) {
    if (is_skipped(line)) continue;
    header_line = reader.line_number();
    separator = detect_separator(line, source + ":" + std::to_string(header_line));
    header = split_fields(line, separator);
    break;
  }
  if (in.bad()) throw std::invalid_argument(source + ": read error before the header row");
  if (header.empty()) throw std::invalid_argument(source + ": no header row (" + expected + ")");

  // Column of each wanted name; every other column is ignored.
  const std::string at_header = source + ":" + std::to_string(header_line);
  table.header_line = header_line;
  if (separator != ',')
    table.notices.push_back(at_header + ": fields separated by " + separator_name(separator) +
                            " (the header has no comma)");
  std::map<std::string, int> column_of;
  for (int c = 0; c < static_cast<int>(header.size()); ++c) {
    const auto [it, inserted] = column_of.emplace(header[c], c);
    if (!inserted)
      throw std::invalid_argument(at_header + ": column '" + message_excerpt(header[c]) +
                                  "' appears twice (fields " + std::to_string(it->second + 1) +
                                  " and " + std::to_string(c + 1) + ")");
  }
  std::vector<int> columns;
  std::vector<bool> used(header.size(), false);
  for (const auto& name : wanted) {
    // The bare name, or the name with a unit suffix (joint1_deg); never both.
    auto it = column_of.find(name);
    std::string unit;
    for (const auto& suffix : column_unit_suffixes()) {
      const auto with_unit = column_of.find(name + "_" + suffix);
      if (with_unit == column_of.end()) continue;
      if (it != column_of.end())
        throw std::invalid_argument(at_header + ": columns '" + it->first + "' and '" +
                                    with_unit->first + "' both give " + name +
                                    "; expected one of them");
      it = with_unit;
      unit = suffix;
    }
    if (it == column_of.end()) {
      // A header such as "leg1;leg2,..." mixes separators: name what was found.
      std::string found;
      if (separator == ',' && line.find(';') != std::string::npos) found = "';'";
      if (separator == ',' && line.find('\t') != std::string::npos)
        found += std::string(found.empty() ? "" : " and ") + "tabs";
      throw std::invalid_argument(
          at_header + ": header has no column '" + name + "' (" + expected +
          (found.empty() ? ")"
                         : "; the header holds commas and " + found +
                               ": expected one separator, commas, throughout the file)"));
    }
    columns.push_back(it->second);
    used[it->second] = true;
    table.column_units.push_back(unit);
    table.column_headers.push_back(it->first);
  }
  for (std::size_t c = 0; c < header.size(); ++c)
    if (!used[c])
      table.notices.push_back(at_header + ": ignoring column '" + message_excerpt(header[c]) +
                              "' (not an actuator or reading of the model)");

  const int num_actuators = static_cast<int>(actuator_names.size());
  // The values row after row, wanted.size() each. The messages' "file:line" strings are built
  // only when thrown: a string per row and field, and a vector per row, were most of the time
  // of reading 10^6 rows.
  const std::size_t per_row = wanted.size();
  std::vector<double> values;
  std::vector<std::string> fields;
  std::size_t num_rows = 0;
  while (reader.next(line)) {
    if (is_skipped(line)) continue;
    split_fields(line, separator, fields);
    const int line_number = reader.line_number();
    const auto at = [&] { return source + ":" + std::to_string(line_number); };
    if (fields.size() != header.size())
      throw std::invalid_argument(at() + ": " + std::to_string(fields.size()) +
                                  " fields, expected " + std::to_string(header.size()) +
                                  " as in the header");
    if ((num_rows + 1) * table_bytes_per_row(per_row) > limits.max_table_bytes)
      throw std::invalid_argument(at() + ": the rows read so far need more than the " +
                                  std::to_string(limits.max_table_bytes >> 20) +
                                  " MiB of memory allowed for them; expected a smaller file");
    for (std::size_t w = 0; w < per_row; ++w) {
      const std::string& field = fields[columns[w]];
      // An empty reading is one the sensor did not take (NaN); an actuator value is always
      // known, since it was commanded.
      const bool reading = static_cast<int>(w) >= num_actuators;
      // With ';' or tabs between fields, "1,5" is a decimal comma: never guess what it means.
      if (separator != ',' && field.find(',') != std::string::npos)
        throw std::invalid_argument(at() + ": field '" + wanted[w] + "': '" +
                                    message_excerpt(field) +
                                    "' has a decimal comma (fields are "
                                    "separated by " +
                                    separator_name(separator) +
                                    "); expected a decimal point: export the file with '.' as "
                                    "the decimal mark, or as comma-separated CSV");
      values.push_back(reading && field.empty() ? std::numeric_limits<double>::quiet_NaN()
                                                : parse_value(field, [&] {
                                                    return at() + ": field '" + wanted[w] + "'";
                                                  }));
    }
    ++num_rows;
    table.line_numbers.push_back(line_number);
  }
  // Reading stops at a read error as at the end of the file: tell them apart.
  if (in.bad())
    throw std::invalid_argument(source + ": read error after line " +
                                std::to_string(reader.line_number()));
  if (num_rows == 0) throw std::invalid_argument(source + ": no measurement rows after the header");

  const int m = static_cast<int>(num_rows);
  table.data.actuators.resize(m, num_actuators);
  table.data.readings.resize(m, static_cast<int>(reading_names.size()));
  for (int r = 0; r < m; ++r) {
    const double* row = values.data() + static_cast<std::size_t>(r) * per_row;
    for (int c = 0; c < num_actuators; ++c) table.data.actuators(r, c) = row[c];
    for (int c = 0; c < table.data.readings.cols(); ++c)
      table.data.readings(r, c) = row[num_actuators + c];
  }
  return table;
}

void check_measurements_writable(const Measurements& data,
                                 const std::vector<std::string>& actuator_names,
                                 const std::vector<std::string>& reading_names,
                                 const std::string& comment) {
  const auto check_columns = [](const char* what, const std::vector<std::string>& names,
                                Eigen::Index columns) {
    if (static_cast<Eigen::Index>(names.size()) != columns)
      throw std::invalid_argument(std::string(what) + ": " + std::to_string(names.size()) +
                                  " column names for " + std::to_string(columns) +
                                  " columns; expected one name per column");
  };
  check_columns("actuators", actuator_names, data.actuators.cols());
  check_columns("readings", reading_names, data.readings.cols());
  if (data.readings.rows() != data.actuators.rows())
    throw std::invalid_argument("readings: " + std::to_string(data.readings.rows()) + " rows for " +
                                std::to_string(data.actuators.rows()) +
                                " rows of actuators; expected one per configuration");
  std::vector<std::string> names = actuator_names;
  names.insert(names.end(), reading_names.begin(), reading_names.end());
  for (std::size_t i = 0; i < names.size(); ++i) {
    // The reader splits the header at separators and matches names exactly: a name it
    // could not read back, or one that a spreadsheet would run as a formula, is refused.
    const std::string problem = name_problem(names[i], NameKind::kColumn);
    if (!problem.empty())
      throw std::invalid_argument("column '" + message_excerpt(names[i]) + "': " + problem +
                                  "; expected a name kincal reads back (docs/reliability.md, "
                                  "\"Names\")");
    for (std::size_t k = 0; k < i; ++k)
      if (names[k] == names[i])
        throw std::invalid_argument("column '" + message_excerpt(names[i]) +
                                    "' is given twice; expected one column per name");
  }
  const auto value_text = [](double v) {
    return std::string(std::isnan(v) ? "nan" : std::signbit(v) ? "-inf" : "inf");
  };
  for (Eigen::Index r = 0; r < data.actuators.rows(); ++r)
    for (Eigen::Index c = 0; c < data.actuators.cols(); ++c)
      if (!std::isfinite(data.actuators(r, c)))
        throw std::invalid_argument("actuators[" + std::to_string(r) + ", " + std::to_string(c) +
                                    "] ('" + message_excerpt(actuator_names[c]) + "') is " +
                                    value_text(data.actuators(r, c)) +
                                    "; expected a finite actuator value in every row");
  for (Eigen::Index r = 0; r < data.readings.rows(); ++r)
    for (Eigen::Index c = 0; c < data.readings.cols(); ++c)
      if (std::isinf(data.readings(r, c)))
        throw std::invalid_argument("readings[" + std::to_string(r) + ", " + std::to_string(c) +
                                    "] ('" + message_excerpt(reading_names[c]) + "') is " +
                                    value_text(data.readings(r, c)) +
                                    "; expected a finite reading, or NaN for one not taken");
  if (comment.find('\0') != std::string::npos)
    throw std::invalid_argument(
        "comment: holds a NUL byte, which no measurement file may hold; expected text");
}

std::string measurements_to_csv(const Measurements& data,
                                const std::vector<std::string>& actuator_names,
                                const std::vector<std::string>& reading_names,
                                const std::string& comment) {
  check_measurements_writable(data, actuator_names, reading_names, comment);
  std::ostringstream out;
  if (!comment.empty()) {
    std::istringstream lines(comment);
    std::string line;
    while (std::getline(lines, line)) out << "# " << line << "\n";
  }
  std::vector<std::string> names = actuator_names;
  names.insert(names.end(), reading_names.begin(), reading_names.end());
  out << join(names) << "\n";
  // 17 significant digits: a written file reads back bit for bit.
  out << std::setprecision(std::numeric_limits<double>::max_digits10);
  for (int r = 0; r < data.size(); ++r) {
    for (int c = 0; c < data.actuators.cols(); ++c) out << (c ? "," : "") << data.actuators(r, c);
    // A missing reading is an empty field, as read.
    for (int c = 0; c < data.readings.cols(); ++c) {
      out << ",";
      if (!std::isnan(data.readings(r, c))) out << data.readings(r, c);
    }
    out << "\n";
  }
  return out.str();
}

MeasurementTable read_measurements(const std::string& path, const MeasurementModel& model,
                                   const CsvLimits& limits) {
  MeasurementTable table = read_model_columns(path, model, limits);
  check_sensor_readings(model, table, path);
  return table;
}

std::vector<std::string> column_unit_suffixes() { return UnitRegistry::global().names(); }

void convert_column_units(MeasurementTable& table, const std::vector<std::string>& actuator_units,
                          const std::vector<std::string>& reading_units,
                          const std::string& source) {
  const int na = static_cast<int>(actuator_units.size());
  if (table.data.actuators.cols() != na ||
      table.data.readings.cols() != static_cast<int>(reading_units.size()) ||
      table.column_units.size() != actuator_units.size() + reading_units.size())
    throw std::invalid_argument(source + ": the units do not match the columns read");
  for (std::size_t w = 0; w < table.column_units.size(); ++w) {
    const std::string& suffix = table.column_units[w];
    if (suffix.empty()) continue;
    const bool actuator = static_cast<int>(w) < na;
    const std::string& unit = actuator ? actuator_units[w] : reading_units[w - na];
    if (unit.empty())
      throw std::invalid_argument(source + ":" + std::to_string(table.header_line) + ": column '" +
                                  table.column_headers[w] +
                                  "': a plain number (no unit), but the name carries the unit "
                                  "suffix _" +
                                  suffix + "; expected the name without a suffix");
    // The suffix must be a unit of the column's quantity: its value converts to the column's.
    Unit given, wanted;
    const bool known = UnitRegistry::global().find(suffix, &given);
    UnitRegistry::global().find(unit, &wanted);
    if (!known || given.base != unit) {
      std::string expected;
      const auto units = UnitRegistry::global().units_of(unit);
      for (std::size_t i = 0; i < units.size(); ++i)
        expected += (i == 0 ? "_" : i + 1 == units.size() ? " or _" : ", _") + units[i];
      throw std::invalid_argument(
          source + ":" + std::to_string(table.header_line) + ": column '" +
          table.column_headers[w] + "': " + (actuator ? "actuator" : "reading") + " " +
          table.column_headers[w].substr(0, table.column_headers[w].size() - suffix.size() - 1) +
          " is " + (wanted.quantity.empty() ? "in " + unit : wanted.quantity + " (" + unit + ")") +
          ", but the suffix says " + suffix + "; expected " + expected + " (or no suffix for " +
          unit + ")");
    }
    const double factor = given.factor;
    if (factor == 1) continue;
    auto column = actuator ? table.data.actuators.col(static_cast<int>(w))
                           : table.data.readings.col(static_cast<int>(w) - na);
    column *= factor;  // NaN (not measured) stays NaN
  }
}

void check_sensor_readings(const MeasurementModel& model, MeasurementTable& table,
                           const std::string& source) {
  const MatrixXd& readings = table.data.readings;
  const auto names = model.reading_names();
  for (int r = 0; r < table.data.size(); ++r) {
    const std::string at = source + ":" + std::to_string(table.line_numbers[r]);
    for (std::size_t s = 0; s < model.sensors().size(); ++s) {
      const Sensor& sensor = *model.sensors()[s];
      const int o = model.sensor_reading_offset(static_cast<int>(s)), k = sensor.num_readings();
      for (int i = 0; i < k; ++i) {
        std::string why;
        const double value = readings(r, o + i);
        if (!std::isnan(value) && !sensor.valid_reading(i, value, &why))
          throw std::invalid_argument(at + ": " + names[o + i] + ": " + why);
      }
      const int group = std::max(1, std::min(k, sensor.reading_group_size()));
      for (int g = 0; g < k; g += group) {
        const int size = std::min(group, k - g);
        const int missing =
            static_cast<int>(readings.row(r).segment(o + g, size).array().isNaN().count());
        if (missing == 0 || missing == size) continue;
        std::string empty, given;
        const auto add = [](std::string& list, const std::string& name) {
          list += (list.empty() ? "" : ", ") + name;
        };
        for (int i = g; i < g + size; ++i)
          add(std::isnan(readings(r, o + i)) ? empty : given, names[o + i]);
        throw std::invalid_argument(
            at + ": sensor '" + sensor.name() + "' has " + given + " but not " + empty +
            (size == k ? "; expected all of its readings or none (leave every one empty when "
                         "the sensor did not measure)"
                       : "; expected these readings together or none (leave each empty when "
                         "the sensor did not take it)"));
      }
    }
    if (readings.row(r).array().isNaN().all())
      table.notices.push_back(at + ": no readings in this row (nothing measured; ignored)");
  }
  if (table.data.num_present() == 0)
    throw std::invalid_argument(source + ": every reading is empty; expected measured readings");
}

std::vector<UnreachableRow> find_unreachable_rows(const MeasurementModel& model,
                                                  const VectorXd& params,
                                                  const Measurements& data) {
  // Per chunk of rows, in parallel; the chunks' findings joined in row order.
  std::vector<std::vector<UnreachableRow>> found(
      static_cast<std::size_t>(chunk_count(data.size(), kRowsPerChunk)));
  parallel_chunks(data.size(), kRowsPerChunk, [&](int chunk, int begin, int end) {
    std::vector<UnreachableRow>& bad = found[static_cast<std::size_t>(chunk)];
    auto ws = model.make_workspace();
    VectorXd readings(model.num_readings());
    for (int r = begin; r < end; ++r) {
      if (data.readings.row(r).array().isNaN().all()) continue;  // nothing measured: not used
      const ForwardKinematicsResult fk =
          model.predict(params, data.actuators.row(r).transpose(), readings, nullptr, ws);
      if (!fk.ok()) {
        bad.push_back({r, fk.describe()});
        continue;
      }
      if (!model.sensors_can_miss()) continue;
      // Every measured reading missed: nothing of the row can be used.
      std::string reasons;
      bool any_read = false;
      for (int i = 0; i < model.num_readings() && !any_read; ++i)
        any_read = !std::isnan(data.readings(r, i)) && !std::isnan(readings[i]);
      if (any_read) continue;
      for (int s = 0; s < static_cast<int>(model.sensors().size()); ++s) {
        std::string reason;
        if (model.sensor_reads_at(params, fk.pose, s, &reason)) continue;
        reasons += (reasons.empty() ? "" : "; ") + model.sensors()[s]->name() + ": " + reason;
      }
      bad.push_back({r, "gives no reading (" + reasons + ")"});
    }
  });
  std::vector<UnreachableRow> bad;
  for (const auto& part : found) bad.insert(bad.end(), part.begin(), part.end());
  return bad;
}

std::vector<MissedReading> find_missed_readings(const MeasurementModel& model,
                                                const VectorXd& params, const Measurements& data) {
  if (!model.sensors_can_miss()) return {};
  const Mechanism& mechanism = model.mechanism();
  std::vector<std::vector<MissedReading>> found(
      static_cast<std::size_t>(chunk_count(data.size(), kRowsPerChunk)));
  parallel_chunks(data.size(), kRowsPerChunk, [&](int chunk, int begin, int end) {
    std::vector<MissedReading>& missed = found[static_cast<std::size_t>(chunk)];
    for (int r = begin; r < end; ++r) {
      const ForwardKinematicsResult fk = mechanism.forward_kinematics(
          params.head(mechanism.num_parameters()), data.actuators.row(r).transpose(),
          mechanism.home_pose(), model.forward_kinematics_options());
      if (!fk.ok()) continue;  // find_unreachable_rows reports it
      std::vector<MissedReading> row;
      bool any_read = false;
      for (int s = 0; s < static_cast<int>(model.sensors().size()); ++s) {
        const int o = model.sensor_reading_offset(s), k = model.sensors()[s]->num_readings();
        if (data.readings.row(r).segment(o, k).array().isNaN().all()) continue;  // not measured
        std::string reason;
        if (model.sensor_reads_at(params, fk.pose, s, &reason))
          any_read = true;
        else
          row.push_back({r, s, reason});
      }
      if (any_read) missed.insert(missed.end(), row.begin(), row.end());
    }
  });
  std::vector<MissedReading> missed;
  for (const auto& part : found) missed.insert(missed.end(), part.begin(), part.end());
  return missed;
}

void drop_readings(const MeasurementModel& model, const std::vector<MissedReading>& missed,
                   Measurements& data) {
  for (const MissedReading& m : missed)
    data.readings.row(m.row)
        .segment(model.sensor_reading_offset(m.sensor), model.sensors()[m.sensor]->num_readings())
        .setConstant(std::numeric_limits<double>::quiet_NaN());
}

Measurements drop_rows(const Measurements& data, const std::vector<int>& rows) {
  Measurements out;
  const int m = data.size() - static_cast<int>(rows.size());
  out.actuators.resize(m, data.actuators.cols());
  out.readings.resize(m, data.readings.cols());
  std::size_t next = 0;
  int k = 0;
  for (int r = 0; r < data.size(); ++r) {
    if (next < rows.size() && rows[next] == r) {
      ++next;
      continue;
    }
    out.actuators.row(k) = data.actuators.row(r);
    out.readings.row(k) = data.readings.row(r);
    ++k;
  }
  return out;
}

}  // namespace kincal
