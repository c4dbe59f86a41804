// kincal fk: forward kinematics of a model file for given actuator values, one configuration
// (--actuators) or a table of them (--data).

#include "kincal/cli/command_kinematics.hpp"
#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/model_args.hpp"

namespace kincal::cli {

int run_fk(const Args& args) {
  po::options_description options(std::string("kincal fk (") + kPoseConvention + ")");
  options.add_options()("model", po::value<std::string>(), "model file (JSON)")(
      "actuators", po::value<std::string>(),
      "commanded actuator values q1,q2,... in the actuators' units (mm for prismatic joints "
      "such as hexapod legs, rad for revolute joints), or each with its unit: 90deg, 1.2rad, "
      "350mm, 0.35m")(
      "data", po::value<std::string>(),
      "instead of --actuators: a CSV file with the actuator columns (a measurement file; "
      "other columns are ignored; a column may carry a unit suffix, joint1_deg): one result "
      "per row, failures as statuses");
  add_deprecated_alias(options, "legs", "actuators", po::value<std::string>());
  add_table_outputs(options);
  add_data_size_option(options);
  po::variables_map vm;
  if (!parse_command_line("fk", args, options, vm)) return 0;
  OutputPlan plan(console_output());  // standard output must not be an input
  if (vm.count("model")) plan.input("--model", vm["model"].as<std::string>());
  const std::string option = "actuators";
  if (vm.count("data")) {
    if (vm.count(option)) throw CliError("give --" + option + " or --data, not both");
    plan.input("--data", vm["data"].as<std::string>());
    if (!vm.count("model")) throw CliError("--model FILE is required");
    plan.check();  // before the model is read; run_table checks again with its outputs
    const auto model = load_model_option(vm);
    OutputPlan table_plan = plan;
    return run_table("fk", vm, table_plan, *model, KinematicsTableRequest());
  }
  if (vm.count("out")) throw CliError("--out writes the table of --data; give --data FILE");
  const std::string json_file = json_output(vm);
  if (!json_file.empty()) plan.output("--json", json_file);
  plan.check();
  if (!vm.count(option)) throw CliError("--actuators q1,q2,... (or --data FILE) is required");
  const auto model = load_model_option(vm);
  const KinematicsRow row = forward_at(*model, vm[option].as<std::string>(), option_flag(option));
  if (!json_file.empty()) {
    const auto json = kinematics_row_document(false, vm["model"].as<std::string>(), *model, row);
    plan.write({{"--json", json.dump(2) + "\n"}});
    if (plan.to_stdout("--json")) return 0;
  }
  out() << forward_row_text(*model, row);
  return 0;
}

}  // namespace kincal::cli
