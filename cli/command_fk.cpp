// kincal fk: forward kinematics of a model file for given actuator values.

#include <cstdio>

#include "kincal/cli/command_kinematics.hpp"
#include "kincal/cli/model_args.hpp"

namespace kincal::cli {

namespace {

constexpr double kDegrees = 180.0 / 3.14159265358979323846;

}  // namespace

int run_fk(const Args& args) {
  po::options_description options(std::string("kincal fk (") + kPoseConvention + ")");
  options.add_options()("model", po::value<std::string>(), "model file (JSON)")(
      "actuators", po::value<std::string>(),
      "commanded actuator values q1,q2,... in the actuators' units (mm for prismatic joints "
      "such as hexapod legs, rad for revolute joints): a row of the measurement file")(
      "legs", po::value<std::string>(), "the same as --actuators (its older name)");
  po::variables_map vm;
  if (!parse_command_line("fk", args, options, vm)) return 0;
  OutputPlan plan;  // no outputs; standard output must not be the model file
  if (vm.count("model")) plan.input("--model", vm["model"].as<std::string>());
  plan.check();
  if (vm.count("actuators") && vm.count("legs"))
    throw CliError("give --actuators or --legs (the same option), not both");
  const std::string option = vm.count("legs") ? "legs" : "actuators";
  if (!vm.count(option)) throw CliError("--actuators q1,q2,... is required");
  const auto model = load_model_option(vm);
  const Mechanism& mechanism = model->mechanism();
  const int n = mechanism.num_actuators();
  std::string expected;
  for (const auto& a : mechanism.actuators())
    expected += (expected.empty() ? "" : ",") + a.name + " (" + a.unit + ")";
  const auto values = parse_numbers(vm[option].as<std::string>(), n, option, expected);
  const VectorXd q = Eigen::Map<const VectorXd>(values.data(), n);
  const VectorXd params = model->parameters().nominal_values();
  const auto mech = params.head(model->mechanism().num_parameters());
  const ForwardKinematicsResult fk = model->mechanism().forward_kinematics(
      mech, q, model->mechanism().home_pose(), model->forward_kinematics_options());
  if (!fk.ok())
    throw CliError("--" + option + " '" + vm[option].as<std::string>() + "': forward kinematics " +
                   fk.describe() + "; expected actuator values the model can reach");
  VectorXd readings(model->num_readings());
  model->predict_at_pose(params, fk.pose, readings);
  if (!readings.allFinite())
    throw CliError("--" + option + " '" + vm[option].as<std::string>() +
                   "': the readings at this pose are not finite numbers (the arithmetic "
                   "overflows); expected actuator values of the machine's workspace");
  const Vector3d& t = fk.pose.translation;
  const Vector3d zyx = euler_zyx(fk.pose.rotation) * kDegrees;
  std::printf("position_mm   %.6f %.6f %.6f\n", t[0], t[1], t[2]);
  std::printf("rotation_deg  %.6f %.6f %.6f   (rx ry rz, R = Rz(rz) Ry(ry) Rx(rx))\n", zyx[2],
              zyx[1], zyx[0]);
  const auto names = model->reading_names();
  for (int k = 0; k < readings.size(); ++k)
    std::printf("%-13s %.6f\n", names[k].c_str(), readings[k]);
  return 0;
}

}  // namespace kincal::cli
