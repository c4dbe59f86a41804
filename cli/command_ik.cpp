// kincal ik: actuator values of a model file at a given pose (--pose) or at each pose of a
// table (--data).

#include <cstdio>

#include "kincal/cli/command_kinematics.hpp"
#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/model_args.hpp"

namespace kincal::cli {

namespace {

// --near's actuator values, or none.
VectorXd near_option(const po::variables_map& vm, const MeasurementModel& model) {
  if (!vm.count("near")) return {};
  const int n = model.mechanism().num_actuators();
  const auto v =
      parse_numbers(vm["near"].as<std::string>(), n, "near", "one value per actuator, in its unit");
  return Eigen::Map<const VectorXd>(v.data(), n);
}

}  // namespace

int run_ik(const Args& args) {
  po::options_description options(std::string("kincal ik (") + kPoseConvention + ")");
  options.add_options()("model", po::value<std::string>(), "model file (JSON)")(
      "pose", po::value<std::string>(),
      "x,y,z,rx,ry,rz: mm and degrees (write --pose=-5,... when it starts with a minus)")(
      "data", po::value<std::string>(),
      "instead of --pose: a CSV file with columns x_mm,y_mm,z_mm,rx_deg,ry_deg,rz_deg (other "
      "columns are ignored): one result per row, failures as statuses")(
      "near", po::value<std::string>(),
      "q1,q2,...: the solution nearest these actuator values (a serial arm's branch), in "
      "the actuators' units; default: from home")(
      "all", po::bool_switch(),
      "with --pose: every distinct solution found (from --near or home and 200 starts over "
      "the joints' ranges), nearest first")(
      "seeds", po::bool_switch(),
      "with --data: each row's solution is the one nearest the configuration in its own "
      "actuator columns (the model's actuator names, unit suffixes such as _deg allowed): a "
      "start per row, e.g. where the robot is");
  // --poses is a count of configurations in every other command; a table is --data, as in fk.
  add_deprecated_alias(options, "poses", "data", po::value<std::string>());
  add_table_outputs(options);
  add_data_size_option(options);
  po::variables_map vm;
  if (!parse_command_line("ik", args, options, vm)) return 0;
  OutputPlan plan(console_output());  // standard output must not be an input
  if (vm.count("model")) plan.input("--model", vm["model"].as<std::string>());
  if (vm.count("data")) {
    if (vm.count("pose")) throw CliError("give --pose or --data, not both");
    plan.input("--data", vm["data"].as<std::string>());
    if (!vm.count("model")) throw CliError("--model FILE is required");
    if (vm["all"].as<bool>()) throw CliError("--all takes one --pose, not a table (--data)");
    const bool seeds = vm["seeds"].as<bool>();
    if (seeds && vm.count("near")) throw CliError("give --near or --seeds, not both");
    plan.check();
    const auto model = load_model_option(vm);
    KinematicsTableRequest request;
    request.inverse = true;
    request.seeds = seeds;
    request.near = near_option(vm, *model);
    OutputPlan table_plan = plan;
    return run_table("ik", vm, table_plan, *model, request);
  }
  if (vm.count("out")) throw CliError("--out writes the table of --data; give --data FILE");
  if (vm["seeds"].as<bool>()) throw CliError("--seeds reads a start per row of --data FILE");
  const std::string json_file = json_output(vm);
  if (!json_file.empty()) plan.output("--json", json_file);
  plan.check();
  if (!vm.count("pose")) throw CliError("--pose x,y,z,rx,ry,rz (or --data FILE) is required");
  const auto model = load_model_option(vm);
  const VectorXd near = near_option(vm, *model);
  const std::string text = vm["pose"].as<std::string>();
  const VectorXd* start = near.size() ? &near : nullptr;
  if (vm["all"].as<bool>()) {
    const std::vector<KinematicsRow> solutions =
        inverse_solutions_at(*model, text, "--pose", start);
    if (!json_file.empty()) {
      const auto json =
          kinematics_solutions_document(vm["model"].as<std::string>(), *model, solutions);
      plan.write({{"--json", json.dump(2) + "\n"}});
      if (plan.to_stdout("--json")) return 0;
    }
    out() << inverse_solutions_text(*model, solutions, start != nullptr);
    return 0;
  }
  const KinematicsRow row = inverse_at(*model, text, "--pose", start);
  if (!json_file.empty()) {
    const auto json = kinematics_row_document(true, vm["model"].as<std::string>(), *model, row);
    plan.write({{"--json", json.dump(2) + "\n"}});
    if (plan.to_stdout("--json")) return 0;
  }
  out() << inverse_row_text(*model, row) << actuator_units_line(*model);
  return 0;
}

}  // namespace kincal::cli
