// kincal fk: forward kinematics of a model file for given leg lengths.

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
      "legs", po::value<std::string>(),
      "commanded leg lengths l1,...,l6 in mm (the actuator values of the measurement file)");
  po::variables_map vm;
  if (!parse_command_line("fk", args, options, vm)) return 0;
  OutputPlan plan;  // no outputs; standard output must not be the model file
  if (vm.count("model")) plan.input("--model", vm["model"].as<std::string>());
  plan.check();
  if (!vm.count("legs")) throw CliError("--legs l1,...,l6 is required");
  const auto model = load_model_option(vm);
  const int n = model->mechanism().num_actuators();
  const auto legs = parse_numbers(vm["legs"].as<std::string>(), n, "legs",
                                  std::to_string(n) + " leg lengths in mm");
  const VectorXd q = Eigen::Map<const VectorXd>(legs.data(), n);
  const VectorXd params = model->parameters().nominal_values();
  const auto mech = params.head(model->mechanism().num_parameters());
  const ForwardKinematicsResult fk = model->mechanism().forward_kinematics(
      mech, q, model->mechanism().home_pose(), model->forward_kinematics_options());
  if (!fk.ok())
    throw CliError("--legs '" + vm["legs"].as<std::string>() + "': forward kinematics " +
                   fk.describe() + "; expected leg lengths the model can reach");
  VectorXd readings(model->num_readings());
  model->predict_at_pose(params, fk.pose, readings);
  if (!readings.allFinite())
    throw CliError("--legs '" + vm["legs"].as<std::string>() +
                   "': the readings at this pose are not finite numbers (the arithmetic "
                   "overflows); expected leg lengths of the machine's workspace");
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
