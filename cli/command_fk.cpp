// kincal fk: forward kinematics of a model file for given actuator values, one configuration
// (--actuators) or a table of them (--data).

#include <cmath>
#include <cstdio>

#include "kincal/cli/command_kinematics.hpp"
#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal::cli {

namespace {

KinematicsRow forward_from_values(const MeasurementModel& model, const std::vector<double>& q) {
  return forward_row(model,
                     Eigen::Map<const VectorXd>(q.data(), static_cast<Eigen::Index>(q.size())));
}

// --actuators: numbers in the actuators' own units, each optionally followed by a unit
// (90deg, 1.2rad, 350mm, 0.35m), converted to that unit. A revolute joint's value beyond one
// turn without a unit is refused as degrees, as in a measurement file.
std::vector<double> parse_actuators(const std::string& text, const std::string& option,
                                    const MeasurementModel& model, const std::string& expected) {
  const auto& actuators = model.mechanism().actuators();
  std::vector<std::string> units;
  std::string numbers;
  std::string::size_type start = 0;
  while (true) {
    const auto comma = text.find(',', start);
    std::string field = text.substr(start, comma - start);
    std::string unit;
    for (const char* suffix : {"deg", "rad", "mm", "m"}) {
      const std::string s = suffix;
      if (field.size() > s.size() && field.compare(field.size() - s.size(), s.size(), s) == 0) {
        unit = s;
        field.erase(field.size() - s.size());
        break;
      }
    }
    units.push_back(unit);
    numbers += (numbers.empty() && start == 0 ? "" : ",") + field;
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  std::vector<double> q =
      parse_numbers(numbers, static_cast<int>(actuators.size()), option, expected);
  for (std::size_t i = 0; i < q.size(); ++i) {
    const std::string& own = actuators[i].unit;
    const std::string& unit = units[i];
    const std::string value = option_flag(option) + " '" + text + "': " + actuators[i].name + " = ";
    if (unit.empty()) {
      if (own == kRadian && std::abs(q[i]) > 2 * M_PI * (1 + 1e-9)) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%g", q[i]);
        throw CliError(value + buf +
                       " is beyond one turn, which looks like degrees; revolute joints take "
                       "radians: write " +
                       buf + "deg (a unit after each value: deg, rad, mm, m) or give radians");
      }
      continue;
    }
    const double factor = own == kRadian ? (unit == "deg"   ? kRadiansPerDegree
                                            : unit == "rad" ? 1
                                                            : 0)
                                         : (unit == "m"    ? 1000
                                            : unit == "mm" ? 1
                                                           : 0);
    if (factor == 0)
      throw CliError(
          value + "a value in " + unit + ", but " + actuators[i].name + " is " +
          (own == kRadian ? "an angle: expected deg or rad" : "a length: expected mm or m"));
    q[i] *= factor;
  }
  return q;
}

}  // namespace

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
    return run_table("fk", vm, table_plan, *model, "data", model->mechanism().actuator_names(),
                     forward_from_values);
  }
  if (vm.count("out")) throw CliError("--out writes the table of --data; give --data FILE");
  const std::string json_file = json_output(vm);
  if (!json_file.empty()) plan.output("--json", json_file);
  plan.check();
  if (!vm.count(option)) throw CliError("--actuators q1,q2,... (or --data FILE) is required");
  const auto model = load_model_option(vm);
  const Mechanism& mechanism = model->mechanism();
  std::string expected;
  for (const auto& a : mechanism.actuators())
    expected += (expected.empty() ? "" : ",") + a.name + " (" + a.unit + ")";
  const std::string text = vm[option].as<std::string>();
  const KinematicsRow row =
      forward_from_values(*model, parse_actuators(text, option, *model, expected));
  if (row.status == "overflow")
    throw CliError(option_flag(option) + " '" + text +
                   "': the readings at this pose are not finite numbers (the arithmetic "
                   "overflows); expected actuator values of the machine's workspace");
  if (!row.ok())
    throw CliError(option_flag(option) + " '" + text + "': " + row.reason +
                   "; expected actuator values the model can reach");
  if (!json_file.empty()) {
    nlohmann::ordered_json json = {
        {"format", "kincal-fk"}, {"version", 1}, {"model", vm["model"].as<std::string>()}};
    json.update(row_json(*model, row));
    plan.write({{"--json", json.dump(2) + "\n"}});
    if (plan.to_stdout("--json")) return 0;
  }
  out() << format_text("position_mm   %.6f %.6f %.6f\n", row.pose[0], row.pose[1], row.pose[2]);
  out() << format_text("rotation_deg  %.6f %.6f %.6f   (rx ry rz, R = Rz(rz) Ry(ry) Rx(rx))\n",
                       row.pose[3], row.pose[4], row.pose[5]);
  const auto names = model->reading_names();
  for (int k = 0; k < row.readings.size(); ++k)
    out() << format_text("%-13s %.6f\n", names[k].c_str(), row.readings[k]);
  return 0;
}

}  // namespace kincal::cli
