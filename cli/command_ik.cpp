// kincal ik: actuator values of a model file at a given pose (--pose) or at each pose of a
// table (--data).

#include <cstdio>

#include "kincal/cli/command_kinematics.hpp"
#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/model_args.hpp"

namespace kincal::cli {

namespace {

KinematicsRow inverse_from_values(const MeasurementModel& model, const std::vector<double>& v,
                                  const VectorXd* near) {
  return inverse_row(model, {v[0], v[1], v[2], v[3], v[4], v[5]}, near);
}

// The actuator values of a row, one per line with its name, then the readings.
void print_row(const MeasurementModel& model, const KinematicsRow& row) {
  const auto& names = model.mechanism().actuator_names();
  // Micrometres for lengths; for angles nanoradians, a micrometre at a metre's reach.
  const auto& actuators = model.mechanism().actuators();
  for (int i = 0; i < row.actuators.size(); ++i)
    out() << format_text(actuators[i].unit == kRadian ? "%-8s %.9f\n" : "%-8s %.6f\n",
                         names[i].c_str(), row.actuators[i]);
  const auto reading_names = model.reading_names();
  for (int k = 0; k < row.readings.size(); ++k)
    out() << format_text("%-8s %.6f\n", reading_names[k].c_str(), row.readings[k]);
}

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
    const VectorXd near = near_option(vm, *model);
    OutputPlan table_plan = plan;
    std::vector<std::string> columns = kPoseColumns;
    if (seeds)
      for (const std::string& name : model->mechanism().actuator_names()) columns.push_back(name);
    return run_table("ik", vm, table_plan, *model, "data", columns,
                     [&](const MeasurementModel& m, const std::vector<double>& v) {
                       if (!seeds) return inverse_from_values(m, v, near.size() ? &near : nullptr);
                       // This row's own start: the configuration in its actuator columns.
                       const VectorXd seed = Eigen::Map<const VectorXd>(
                           v.data() + 6, static_cast<Eigen::Index>(v.size() - 6));
                       return inverse_from_values(m, v, &seed);
                     });
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
  const std::vector<double> pose =
      parse_numbers(text, 6, "pose", "x,y,z in mm and rx,ry,rz in degrees");
  if (vm["all"].as<bool>()) {
    const std::vector<KinematicsRow> solutions =
        inverse_solutions(*model, {pose[0], pose[1], pose[2], pose[3], pose[4], pose[5]},
                          near.size() ? &near : nullptr);
    if (solutions.empty())
      throw CliError("--pose '" + text +
                     "': no solution found from 201 starts; expected a pose "
                     "the model can reach");
    if (!json_file.empty()) {
      nlohmann::ordered_json json = {{"format", "kincal-ik"},
                                     {"version", 1},
                                     {"model", vm["model"].as<std::string>()},
                                     {"solutions", nlohmann::ordered_json::array()}};
      for (const KinematicsRow& s : solutions) json["solutions"].push_back(row_json(*model, s));
      plan.write({{"--json", json.dump(2) + "\n"}});
      if (plan.to_stdout("--json")) return 0;
    }
    for (std::size_t k = 0; k < solutions.size(); ++k) {
      out() << format_text("solution %zu of %zu%s\n", k + 1, solutions.size(),
                           k == 0 ? (near.size() ? " (nearest --near)" : " (nearest home)") : "");
      print_row(*model, solutions[k]);
    }
    return 0;
  }
  const KinematicsRow row = inverse_from_values(*model, pose, near.size() ? &near : nullptr);
  if (row.status == "overflow")
    throw CliError("--pose '" + text +
                   "': the actuator values or readings at this pose are not finite numbers (the "
                   "arithmetic overflows); expected a pose near the machine's workspace");
  if (!row.ok())
    throw CliError("--pose '" + text + "': " + row.reason +
                   "; expected a pose the model can reach");
  if (!json_file.empty()) {
    nlohmann::ordered_json json = {
        {"format", "kincal-ik"}, {"version", 1}, {"model", vm["model"].as<std::string>()}};
    json.update(row_json(*model, row));
    plan.write({{"--json", json.dump(2) + "\n"}});
    if (plan.to_stdout("--json")) return 0;
  }
  print_row(*model, row);
  const auto& actuators = model->mechanism().actuators();
  // The unit of each actuator value above, last so that the lines above stay name-value.
  std::string units;
  for (const auto& a : actuators) units += (units.empty() ? "" : ", ") + a.name + " " + a.unit;
  out() << format_text("(actuator units: %s)\n", units.c_str());
  return 0;
}

}  // namespace kincal::cli
