#include "kincal/cli/command_kinematics.hpp"

#include <algorithm>
#include <iostream>

#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/framework/calibration/data_checks.hpp"
#include "kincal/framework/calibration/measurement_file.hpp"

namespace kincal::cli {

void add_table_outputs(po::options_description& options) {
  options.add_options()("out", po::value<std::string>(),
                        "with a table input: write the results as CSV to FILE (default: "
                        "standard output, unless --json is given)");
  add_json_option(options, "the result");
}

int run_table(const std::string& command, const po::variables_map& vm, OutputPlan& plan,
              const MeasurementModel& model, const std::string& input_option,
              const std::vector<std::string>& columns,
              const std::function<KinematicsRow(const MeasurementModel&,
                                                const std::vector<double>&)>& compute) {
  const std::string input_file = vm[input_option].as<std::string>();
  const std::string json_file = json_output(vm);
  const std::string csv_file =
      vm.count("out") ? vm["out"].as<std::string>() : (json_file.empty() ? "-" : "");
  if (!csv_file.empty()) plan.output("--out", csv_file);
  if (!json_file.empty()) plan.output("--json", json_file);
  plan.check();

  MeasurementTable table;
  try {
    table = read_measurements(input_file, columns, {}, data_limits(vm));
    // fk reads actuator columns, ik pose columns (whose names say mm and deg already) and,
    // with --seeds, the actuator columns after them: those take unit suffixes.
    const std::vector<std::string> actuator_names = model.mechanism().actuator_names();
    const std::size_t na = actuator_names.size();
    if (columns.size() >= na &&
        std::equal(actuator_names.begin(), actuator_names.end(), columns.end() - na)) {
      std::vector<std::string> units(columns.size() - na, "");
      for (const auto& a : model.mechanism().actuators()) units.push_back(a.unit);
      convert_column_units(table, units, {}, input_file);
      if (columns.size() == na) {
        const std::string hint =
            check_data_units(model, model.parameters().nominal_values(), table);
        if (!hint.empty()) throw CliError(input_file + ": " + hint);
      }
    }
  } catch (const std::invalid_argument& e) {
    throw measurement_file_error(e);
  }
  // A measurement file given to fk has reading columns: expected there, not worth a note.
  // The actuator columns of a table of poses (ik) are not "not an actuator": one note says
  // how they would be used.
  int actuator_columns = 0;
  for (const auto& n : table.notices) {
    bool reading_column = false, actuator_column = false;
    for (const auto& name : model.reading_names())
      reading_column =
          reading_column || n.find("ignoring column '" + name + "'") != std::string::npos;
    for (const auto& name : model.mechanism().actuator_names())
      actuator_column =
          actuator_column || n.find("ignoring column '" + name + "'") != std::string::npos;
    actuator_columns += actuator_column;
    if (!reading_column && !actuator_column) note(command, n);
  }
  if (actuator_columns > 0)
    note(command, input_file + ": the actuator columns are not read" +
                      (command == "ik" ? std::string(" (--seeds starts each row from them)")
                                       : std::string()));
  std::vector<KinematicsRow> rows;
  int failures = 0;
  for (int r = 0; r < table.data.size(); ++r) {
    std::vector<double> values(table.data.actuators.cols());
    for (Eigen::Index c = 0; c < table.data.actuators.cols(); ++c)
      values[c] = table.data.actuators(r, c);
    rows.push_back(compute(model, values));
    rows.back().line = table.line_numbers[r];
    failures += !rows.back().ok();
  }
  std::vector<std::pair<std::string, std::string>> outputs;
  if (!json_file.empty())
    outputs.push_back({"--json", rows_json("kincal-" + command, vm["model"].as<std::string>(),
                                           input_file, model, rows)
                                         .dump(2) +
                                     "\n"});
  if (!csv_file.empty()) outputs.push_back({"--out", rows_csv(model, rows)});
  plan.write(outputs);
  if (failures == 0) return 0;
  err() << "kincal " << command << ": " << failures << " of " << rows.size()
        << " rows failed (see their status and reason)\n";
  return 1;
}

}  // namespace kincal::cli
