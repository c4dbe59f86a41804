#include "kincal/cli/command_kinematics.hpp"

#include <iostream>

#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/model_args.hpp"

namespace kincal::cli {

void add_table_outputs(po::options_description& options) {
  options.add_options()("out", po::value<std::string>(),
                        "with a table input: write the results as CSV to FILE (default: "
                        "standard output, unless --json is given)");
  add_json_option(options, "the result");
}

int run_table(const std::string& command, const po::variables_map& vm, OutputPlan& plan,
              const MeasurementModel& model, KinematicsTableRequest request) {
  request.data_file = vm["data"].as<std::string>();
  request.limits = data_limits(vm);
  const std::string json_file = json_output(vm);
  const std::string csv_file =
      vm.count("out") ? vm["out"].as<std::string>() : (json_file.empty() ? "-" : "");
  if (!csv_file.empty()) plan.output("--out", csv_file);
  if (!json_file.empty()) plan.output("--json", json_file);
  plan.check();

  KinematicsTable table;
  try {
    table = kinematics_table(model, request);
  } catch (const std::invalid_argument& e) {
    throw measurement_file_error(e);
  }
  for (const std::string& n : table.notes) note(command, n);
  std::vector<std::pair<std::string, std::string>> outputs;
  if (!json_file.empty())
    outputs.push_back({"--json", rows_json("kincal-" + command, vm["model"].as<std::string>(),
                                           request.data_file, model, table.rows)
                                         .dump(2) +
                                     "\n"});
  if (!csv_file.empty()) outputs.push_back({"--out", rows_csv(model, table.rows)});
  plan.write(outputs);
  if (table.failures == 0) return 0;
  err() << "kincal " << command << ": " << table.failures << " of " << table.rows.size()
        << " rows failed (see their status and reason)\n";
  return 1;
}

}  // namespace kincal::cli
