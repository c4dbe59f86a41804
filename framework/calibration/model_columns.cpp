// The columns of a measurement file for a model: its actuators, and each sensor's readings
// under their own names or under one of the sensor's alternative conventions (an orientation
// as roll-pitch-yaw or a quaternion; Sensor::alternative_columns), converted here into the
// readings; names a sensor refuses as ambiguous (Sensor::refused_columns) are an error.
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/calibration/measurement_file.hpp"

namespace kincal {

namespace {

// Where each of the model's readings comes from: a column of its own, or a convention's.
struct ReadingSource {
  int alternative = -1;  ///< index into the plan's alternatives, or -1: the reading's own column
  int column = 0;        ///< the (first) column read for it, among the reading columns
};

struct ColumnPlan {
  std::vector<std::string> columns;  ///< the reading columns to read, in order
  std::vector<std::string> units;    ///< their units ("mm", "rad", "" plain)
  std::vector<ReadingSource> sources;
  std::vector<ReadingColumns> alternatives;  ///< the conventions used
};

// The header field naming `name`, bare or with a unit suffix, or nullptr.
const std::string* find_column(const std::vector<std::string>& header, const std::string& name) {
  for (const auto& field : header) {
    if (field == name) return &field;
    for (const auto& suffix : column_unit_suffixes())
      if (field == name + "_" + suffix) return &field;
  }
  return nullptr;
}

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

ColumnPlan plan_columns(const MeasurementModel& model, const CsvHeader& header,
                        const std::string& path) {
  const std::string at = path + ":" + std::to_string(header.line);
  const auto names = model.reading_names();
  const auto units = model.reading_units();
  ColumnPlan plan;
  for (std::size_t s = 0; s < model.sensors().size(); ++s) {
    const Sensor& sensor = *model.sensors()[s];
    const int offset = model.sensor_reading_offset(static_cast<int>(s));
    for (const RefusedColumns& refused : sensor.refused_columns())
      for (const auto& name : refused.columns)
        if (const std::string* field = find_column(header.fields, name))
          throw std::invalid_argument(at + ": column '" + message_excerpt(*field) +
                                      "' of sensor '" + sensor.name() + "': " + refused.why);
    // At most one convention, given whole, and never beside the readings it replaces.
    int used = -1;
    const std::vector<ReadingColumns> alternatives = sensor.alternative_columns();
    for (std::size_t a = 0; a < alternatives.size(); ++a) {
      const ReadingColumns& alt = alternatives[a];
      std::vector<std::string> present, absent;
      for (const auto& c : alt.columns)
        (find_column(header.fields, c) ? present : absent).push_back(c);
      if (present.empty()) continue;
      if (!absent.empty())
        throw std::invalid_argument(at + ": columns " + join(present) + " give " + alt.convention +
                                    " of sensor '" + sensor.name() + "', but " + join(absent) +
                                    (absent.size() > 1 ? " are" : " is") +
                                    " missing; expected all of " + join(alt.columns));
      if (used >= 0)
        throw std::invalid_argument(
            at + ": sensor '" + sensor.name() + "' has columns in two conventions, " +
            alternatives[used].convention + " and " + alt.convention + "; expected one of them");
      for (int r = alt.first_reading; r < alt.first_reading + alt.readings; ++r)
        if (const std::string* field = find_column(header.fields, names[offset + r]))
          throw std::invalid_argument(at + ": columns '" + message_excerpt(*field) + "' and " +
                                      join(alt.columns) + " both give the " + alt.convention +
                                      " readings of sensor '" + sensor.name() +
                                      "'; expected one of them");
      used = static_cast<int>(a);
    }
    for (int r = 0; r < sensor.num_readings(); ++r) {
      if (used >= 0 && r >= alternatives[used].first_reading &&
          r < alternatives[used].first_reading + alternatives[used].readings) {
        if (r == alternatives[used].first_reading) {
          plan.alternatives.push_back(alternatives[used]);
          const ReadingColumns& alt = plan.alternatives.back();
          plan.sources.push_back({static_cast<int>(plan.alternatives.size()) - 1,
                                  static_cast<int>(plan.columns.size())});
          plan.columns.insert(plan.columns.end(), alt.columns.begin(), alt.columns.end());
          plan.units.insert(plan.units.end(), alt.units.begin(), alt.units.end());
        } else {
          plan.sources.push_back(
              {static_cast<int>(plan.alternatives.size()) - 1, plan.sources.back().column});
        }
        continue;
      }
      // A reading that has conventions but none given: name them all in the message.
      if (!alternatives.empty() && !find_column(header.fields, names[offset + r])) {
        for (const auto& alt : alternatives)
          if (r >= alt.first_reading && r < alt.first_reading + alt.readings) {
            std::string ways;
            for (const auto& a : alternatives)
              if (a.first_reading == alt.first_reading) ways += "; or " + join(a.columns);
            throw std::invalid_argument(
                at + ": header has no column '" + names[offset + r] + "' (sensor '" +
                sensor.name() + "': expected " +
                join(std::vector<std::string>(
                    names.begin() + offset + alt.first_reading,
                    names.begin() + offset + alt.first_reading + alt.readings)) +
                ways + ")");
          }
      }
      plan.sources.push_back({-1, static_cast<int>(plan.columns.size())});
      plan.columns.push_back(names[offset + r]);
      plan.units.push_back(units[offset + r]);
    }
  }
  return plan;
}

}  // namespace

MatrixXd read_configurations(const std::string& path, const MeasurementModel& model,
                             const CsvLimits& limits) {
  MeasurementTable table = read_measurements(path, model.mechanism().actuator_names(), {}, limits);
  std::vector<std::string> units;
  for (const Actuator& a : model.mechanism().actuators()) units.push_back(a.unit);
  convert_column_units(table, units, {}, path);
  return table.data.actuators;
}

MeasurementTable read_model_columns(const std::string& path, const MeasurementModel& model,
                                    const CsvLimits& limits) {
  const CsvHeader header = read_csv_header(path, limits);
  const ColumnPlan plan = plan_columns(model, header, path);
  MeasurementTable table =
      read_measurements(path, model.mechanism().actuator_names(), plan.columns, limits);
  std::vector<std::string> actuator_units;
  for (const auto& a : model.mechanism().actuators()) actuator_units.push_back(a.unit);
  convert_column_units(table, actuator_units, plan.units, path);
  if (plan.alternatives.empty()) return table;

  // The readings of the conventions used, converted row by row.
  const int na = static_cast<int>(actuator_units.size());
  const int k = model.num_readings();
  const MatrixXd columns = std::move(table.data.readings);
  MatrixXd readings(columns.rows(), k);
  std::vector<std::string> column_units(table.column_units.begin(),
                                        table.column_units.begin() + na);
  std::vector<std::string> column_headers(table.column_headers.begin(),
                                          table.column_headers.begin() + na);
  std::vector<double> values;
  std::string why;
  for (int i = 0; i < k; ++i) {
    const ReadingSource& source = plan.sources[i];
    if (source.alternative < 0) {
      readings.col(i) = columns.col(source.column);
      column_units.push_back(table.column_units[na + source.column]);
      column_headers.push_back(table.column_headers[na + source.column]);
      continue;
    }
    // Its unit is stated by the convention: no check may take it for a bare column.
    const ReadingColumns& alt = plan.alternatives[source.alternative];
    column_units.push_back("converted");
    column_headers.push_back(table.column_headers[na + source.column]);
    if (i > 0 && plan.sources[i - 1].alternative == source.alternative) continue;
    const int n = static_cast<int>(alt.columns.size());
    values.resize(static_cast<std::size_t>(n));
    std::vector<double> converted(static_cast<std::size_t>(alt.readings));
    for (Eigen::Index row = 0; row < columns.rows(); ++row) {
      int missing = 0;
      for (int c = 0; c < n; ++c) {
        values[c] = columns(row, source.column + c);
        missing += std::isnan(values[c]);
      }
      const std::string line = path + ":" + std::to_string(table.line_numbers[row]);
      if (missing == n) {
        readings.block(row, i, 1, alt.readings)
            .setConstant(std::numeric_limits<double>::quiet_NaN());
        continue;
      }
      if (missing)
        throw std::invalid_argument(line + ": some of " + join(alt.columns) +
                                    " are empty; expected all of them or none");
      if (!alt.convert(values.data(), converted.data(), &why))
        throw std::invalid_argument(line + ": " + join(alt.columns) + ": " + why);
      for (int r = 0; r < alt.readings; ++r) readings(row, i + r) = converted[r];
    }
  }
  table.data.readings = std::move(readings);
  table.column_units = std::move(column_units);
  table.column_headers = std::move(column_headers);
  return table;
}

}  // namespace kincal
