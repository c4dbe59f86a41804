#include "kincal/framework/calibration/measurement_loading.hpp"

#include <algorithm>
#include <stdexcept>

#include "kincal/framework/calibration/data_checks.hpp"

namespace kincal {

LoadedMeasurements load_measurements(const std::string& path, const MeasurementModel& model,
                                     const VectorXd& params,
                                     const MeasurementLoadOptions& options) {
  return screen_measurements(read_measurements(path, model, options.limits), model, params, options,
                             path);
}

MeasurementTable table_in_memory(Measurements data) {
  MeasurementTable table;
  table.line_numbers.resize(static_cast<std::size_t>(data.size()));
  for (int r = 0; r < data.size(); ++r) table.line_numbers[static_cast<std::size_t>(r)] = r + 1;
  table.data = std::move(data);
  return table;
}

LoadedMeasurements screen_measurements(MeasurementTable table, const MeasurementModel& model,
                                       const VectorXd& params,
                                       const MeasurementLoadOptions& options,
                                       const std::string& path) {
  const bool skip_bad_rows = options.skip_unreachable_rows;
  const std::string& model_file = options.model_file;
  LoadedMeasurements loaded;
  loaded.notes = table.notices;
  // Degrees given as radians, metres as millimetres: an error before anything is solved.
  const std::string units = check_data_units(model, params, table);
  if (!units.empty()) throw std::invalid_argument(path + ": " + units);
  const auto bad = find_unreachable_rows(model, params, table.data);
  // Strokes instead of lengths fail at most rows: say what to do about it.
  const std::string stroke_hint =
      encoder_stroke_hint(model, params, table.data, static_cast<int>(bad.size()));
  const std::string hint = stroke_hint.empty() ? "" : "; hint: " + stroke_hint;
  if (!bad.empty() && static_cast<int>(bad.size()) == table.data.size())
    throw std::invalid_argument(
        path + ": forward kinematics of the model " + model_file + " fails at every row (line " +
        std::to_string(table.line_numbers[bad[0].row]) + ": " + bad[0].reason +
        "); expected actuator values that this model can "
        "reach: check the model's values against the machine, or the data's columns" +
        hint);
  if (!bad.empty() && !skip_bad_rows) {
    std::string list;
    for (std::size_t i = 0; i < bad.size() && i < 5; ++i)
      list += (i ? ", " : "") + std::to_string(table.line_numbers[bad[i].row]) + " (" +
              bad[i].reason + ")";
    if (bad.size() > 5) list += " and " + std::to_string(bad.size() - 5) + " more";
    throw std::invalid_argument(
        path + ": forward kinematics of the model fails at line" + (bad.size() > 1 ? "s " : " ") +
        list +
        "; expected actuator values the model reaches (fix the rows, or drop them with "
        "--skip-bad-rows)" +
        hint);
  }
  std::vector<int> rows;
  for (const auto& b : bad) {
    rows.push_back(b.row);
    loaded.skipped_lines.push_back(table.line_numbers[b.row]);
    loaded.notes.push_back(path + ":" + std::to_string(table.line_numbers[b.row]) +
                           ": skipped, forward kinematics " + b.reason);
  }
  if (!stroke_hint.empty()) loaded.notes.push_back(stroke_hint);
  // Readings a sensor cannot take (no reading: beam misses the plane), in rows that keep
  // others: dropped with a note, as unreachable rows are, and listed in the report.
  const auto missed = find_missed_readings(model, params, table.data);
  for (const auto& m : missed) {
    const std::string line = std::to_string(table.line_numbers[m.row]);
    const std::string& sensor = model.sensors()[m.sensor]->name();
    loaded.dropped_readings.push_back("line " + line + ": " + sensor + ": " + m.reason);
    loaded.notes.push_back(path + ":" + line + ": reading of " + sensor +
                           " dropped, no reading: " + m.reason);
  }
  drop_readings(model, missed, table.data);
  // A copied row is not a second measurement: once only, or the uncertainty shrinks by the
  // square root of the copies and a repeated configuration looks like many.
  const Repeats repeats = find_repeats(table.data);
  if (!repeats.duplicates.empty()) {
    std::string list;
    for (std::size_t i = 0; i < repeats.duplicates.size() && i < 5; ++i)
      list += (i ? ", " : "") + std::to_string(table.line_numbers[repeats.duplicates[i]]) +
              " (= line " + std::to_string(table.line_numbers[repeats.duplicate_of[i]]) + ")";
    if (repeats.duplicates.size() > 5)
      list += " and " + std::to_string(repeats.duplicates.size() - 5) + " more";
    loaded.copied_rows_note = path + ": " + std::to_string(repeats.duplicates.size()) +
                              " row(s) copy an earlier row exactly, readings included, and "
                              "count once: line(s) " +
                              list;
    rows.insert(rows.end(), repeats.duplicates.begin(), repeats.duplicates.end());
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  }
  loaded.duplicate_rows = static_cast<int>(repeats.duplicates.size());
  loaded.repeated_configurations = repeats.repeated_configurations;
  loaded.repeat_rows = repeats.repeat_rows;
  loaded.data = drop_rows(table.data, rows);
  std::size_t next = 0;
  for (int r = 0; r < table.data.size(); ++r) {
    if (next < rows.size() && rows[next] == r) {
      ++next;
      continue;
    }
    loaded.lines.push_back(table.line_numbers[r]);
  }
  if (loaded.data.size() == 0)
    throw std::invalid_argument(path +
                                ": every row was skipped as unreachable; nothing left to use");
  return loaded;
}

}  // namespace kincal
