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
  LoadedData loaded;
  try {
    loaded = kincal::load_measurements(path, model, params, {skip_bad_rows, model_file, limits});
  } catch (const std::invalid_argument& e) {
    throw measurement_file_error(e);
  }
  for (const auto& n : loaded.notes) note(command, n);
  return loaded;
}

void note_copied_rows(const std::string& command, const LoadedData& loaded) {
  if (!loaded.copied_rows_note.empty()) note(command, loaded.copied_rows_note);
}

}  // namespace kincal::cli
