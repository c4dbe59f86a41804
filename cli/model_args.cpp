#include "kincal/cli/model_args.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>

#include "kincal/cli/console.hpp"
#include "kincal/cli/memory_check.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/calibration/data_checks.hpp"
#include "kincal/framework/calibration/measurement_file.hpp"
#include "kincal/models/model_io.hpp"

namespace kincal::cli {

void add_free_fix_options(po::options_description& options) {
  options.add_options()("free", po::value<std::vector<std::string>>()->composing(),
                        "also estimate the parameters matching this glob, e.g. 'leg*.offset' "
                        "(repeatable)")(
      "fix", po::value<std::vector<std::string>>()->composing(),
      "hold the parameters matching this glob at their model values, e.g. gauge.offset "
      "(repeatable; --free and --fix apply in the order given: --fix '*' --free 'base.*')");
}

void apply_free_fix(const po::variables_map& vm, MeasurementModel& model) {
  // In the order given, so that --fix '*' --free 'base.*' frees the base and nothing else.
  std::vector<std::pair<std::string, std::string>> steps;
  if (vm.count(kOptionOrder)) {
    for (const auto& [option, value] :
         vm[kOptionOrder].as<std::vector<std::pair<std::string, std::string>>>())
      if (option == "free" || option == "fix") steps.emplace_back(option, value);
  } else {  // a map filled without parse_command_line: --free, then --fix
    for (const char* option : {"free", "fix"})
      if (vm.count(option))
        for (const auto& pattern : vm[option].as<std::vector<std::string>>())
          steps.emplace_back(option, pattern);
  }
  for (const auto& [option, pattern] : steps) {
    try {
      model.parameters().set_free(pattern, option == "free");
    } catch (const std::invalid_argument& e) {
      const auto& all = model.parameters().all();
      std::string examples;
      for (std::size_t i = 0; i < all.size(); i += std::max<std::size_t>(1, all.size() / 3))
        examples += (examples.empty() ? "" : ", ") + all[i].name;
      throw CliError("--" + option + " '" + pattern +
                     "': matches no parameter of the model (names look like " + examples + ")");
    }
  }
}

namespace {

// What cannot be computed with the model's own values at its own home pose, or "".
std::string unusable_values(const MeasurementModel& model) {
  const Mechanism& mechanism = model.mechanism();
  const VectorXd params = model.parameters().nominal_values();
  const auto mech = params.head(mechanism.num_parameters());
  VectorXd q(mechanism.num_actuators());
  const InverseKinematicsResult home = mechanism.home_actuators(mech, q);
  if (!home.ok()) return "the home actuator values: inverse kinematics " + home.describe();
  if (!q.allFinite()) return "the home actuator values are not finite";
  const ForwardKinematicsResult fk = mechanism.forward_kinematics(
      mech, q, mechanism.home_pose(), model.forward_kinematics_options());
  if (!fk.ok()) return "forward kinematics at the home actuator values " + fk.describe();
  VectorXd readings(model.num_readings());
  model.predict_at_pose(params, fk.pose, readings);
  if (!readings.allFinite()) return "the sensors' readings at the home pose are not finite";
  return "";
}

}  // namespace

std::shared_ptr<MeasurementModel> load_model_option(const po::variables_map& vm) {
  if (!vm.count("model")) throw CliError("--model FILE is required");
  return load_model_file(vm["model"].as<std::string>());
}

std::shared_ptr<MeasurementModel> load_model_file(const std::string& path) {
  auto model = load_model(path);
  const std::string why = unusable_values(*model);
  if (!why.empty())
    throw CliError(path + ": the model's values cannot be computed with: " + why +
                   "; expected the geometry of a real machine (check the values in the file)");
  return model;
}

std::vector<double> parse_numbers(const std::string& text, int count, const std::string& option,
                                  const std::string& expected) {
  std::vector<double> values;
  std::string::size_type start = 0;
  while (true) {
    const auto comma = text.find(',', start);
    const std::string field = text.substr(start, comma - start);
    char* end = nullptr;
    const double v = std::strtod(field.c_str(), &end);
    if (field.empty() || *end != '\0' || !std::isfinite(v))
      throw CliError(option_flag(option) + " '" + text + "': field " +
                     std::to_string(values.size() + 1) + " '" + field +
                     "' is not a finite number (expected " + expected + ")");
    values.push_back(v);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (static_cast<int>(values.size()) != count)
    throw CliError(option_flag(option) + " '" + text + "': " + std::to_string(values.size()) +
                   " numbers, expected " + std::to_string(count) + " (" + expected + ")");
  return values;
}

void note(const std::string& command, const std::string& text) {
  err() << "kincal " << command << ": note: " << text << "\n";
}

void add_data_size_option(po::options_description& options) {
  options.add_options()("max-data-size", po::value<std::string>(),
                        "largest measurement file read, e.g. 8GiB (default 4GiB; the rows are "
                        "also checked against the memory available)");
}

CsvLimits data_limits(const po::variables_map& vm) {
  CsvLimits limits;
  limits.max_table_bytes = static_cast<std::size_t>(
      std::min<std::uint64_t>(available_memory_bytes() / 2, static_cast<std::size_t>(-1)));
  if (!vm.count("max-data-size")) return limits;
  const std::string text = vm["max-data-size"].as<std::string>();
  char* end = nullptr;
  errno = 0;
  const double number = std::strtod(text.c_str(), &end);
  const std::string unit = end ? std::string(end) : "";
  const std::pair<const char*, double> units[] = {
      {"", 1},     {"B", 1},         {"KB", 1e3},      {"MB", 1e6},
      {"GB", 1e9}, {"KiB", 1 << 10}, {"MiB", 1 << 20}, {"GiB", double(1 << 30)}};
  double bytes = -1;
  for (const auto& [name, factor] : units)
    if (unit == name) bytes = number * factor;
  if (end == text.c_str() || errno != 0 || !(bytes >= 1) || bytes > 1e18)
    throw CliError("--max-data-size '" + message_excerpt(text) +
                   "': expected a size such as 500MB or 8GiB (at least 1 byte)");
  limits.max_file_bytes = static_cast<std::size_t>(bytes);
  return limits;
}

CliError measurement_file_error(const std::invalid_argument& e) {
  const std::string what = e.what();
  return CliError(what + (what.find(": larger than the limit of") != std::string::npos
                              ? "; raise the limit with --max-data-size"
                              : ""));
}

LoadedData load_measurements(const std::string& command, const std::string& path,
                             const MeasurementModel& model, const VectorXd& params,
                             bool skip_bad_rows, const std::string& model_file,
                             const CsvLimits& limits) {
  MeasurementTable table;
  try {
    table = read_measurements(path, model, limits);
  } catch (const std::invalid_argument& e) {
    throw measurement_file_error(e);
  }
  for (const auto& n : table.notices) note(command, n);
  // Degrees given as radians, metres as millimetres: an error before anything is solved.
  const std::string units = check_data_units(model, params, table);
  if (!units.empty()) throw CliError(path + ": " + units);
  LoadedData loaded;
  const auto bad = find_unreachable_rows(model, params, table.data);
  // Strokes instead of lengths fail at most rows: say what to do about it.
  const std::string stroke_hint =
      encoder_stroke_hint(model, params, table.data, static_cast<int>(bad.size()));
  const std::string hint = stroke_hint.empty() ? "" : "; hint: " + stroke_hint;
  if (!bad.empty() && static_cast<int>(bad.size()) == table.data.size())
    throw CliError(path + ": forward kinematics of the model " + model_file +
                   " fails at every row (line " + std::to_string(table.line_numbers[bad[0].row]) +
                   ": " + bad[0].reason +
                   "); expected actuator values that this model can "
                   "reach: check the model's values against the machine, or the data's columns" +
                   hint);
  if (!bad.empty() && !skip_bad_rows) {
    std::string list;
    for (std::size_t i = 0; i < bad.size() && i < 5; ++i)
      list += (i ? ", " : "") + std::to_string(table.line_numbers[bad[i].row]) + " (" +
              bad[i].reason + ")";
    if (bad.size() > 5) list += " and " + std::to_string(bad.size() - 5) + " more";
    throw CliError(path + ": forward kinematics of the model fails at line" +
                   (bad.size() > 1 ? "s " : " ") + list +
                   "; expected actuator values the model reaches (fix the rows, or drop them with "
                   "--skip-bad-rows)" +
                   hint);
  }
  std::vector<int> rows;
  for (const auto& b : bad) {
    rows.push_back(b.row);
    loaded.skipped_lines.push_back(table.line_numbers[b.row]);
    note(command, path + ":" + std::to_string(table.line_numbers[b.row]) +
                      ": skipped, forward kinematics " + b.reason);
  }
  if (!stroke_hint.empty()) note(command, stroke_hint);
  // Readings a sensor cannot take (no reading: beam misses the plane), in rows that keep
  // others: dropped with a note, as unreachable rows are, and listed in the report.
  const auto missed = find_missed_readings(model, params, table.data);
  for (const auto& m : missed) {
    const std::string line = std::to_string(table.line_numbers[m.row]);
    const std::string& sensor = model.sensors()[m.sensor]->name();
    loaded.dropped_readings.push_back("line " + line + ": " + sensor + ": " + m.reason);
    note(command,
         path + ":" + line + ": reading of " + sensor + " dropped, no reading: " + m.reason);
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
    throw CliError(path + ": every row was skipped as unreachable; nothing left to use");
  return loaded;
}

void note_copied_rows(const std::string& command, const LoadedData& loaded) {
  if (!loaded.copied_rows_note.empty()) note(command, loaded.copied_rows_note);
}

}  // namespace kincal::cli
