// kincal ik: actuator values of a model file at a given pose.

#include <cstdio>

#include "kincal/cli/command_kinematics.hpp"
#include "kincal/cli/model_args.hpp"

namespace kincal::cli {

int run_ik(const Args& args) {
  po::options_description options(std::string("kincal ik (") + kPoseConvention + ")");
  options.add_options()("model", po::value<std::string>(), "model file (JSON)")(
      "pose", po::value<std::string>(),
      "x,y,z,rx,ry,rz: mm and degrees (write --pose=-5,... when it starts with a minus)");
  po::variables_map vm;
  if (!parse_command_line("ik", args, options, vm)) return 0;
  OutputPlan plan;  // no outputs; standard output must not be the model file
  if (vm.count("model")) plan.input("--model", vm["model"].as<std::string>());
  plan.check();
  if (!vm.count("pose")) throw CliError("--pose x,y,z,rx,ry,rz is required");
  const auto model = load_model_option(vm);
  const auto v =
      parse_numbers(vm["pose"].as<std::string>(), 6, "pose", "x,y,z in mm and rx,ry,rz in degrees");
  constexpr double kRadians = 3.14159265358979323846 / 180.0;
  Pose pose;
  pose.translation = Vector3d(v[0], v[1], v[2]);
  pose.rotation = rotation_from_euler_zyx(Vector3d(v[5], v[4], v[3]) * kRadians);
  const VectorXd params = model->parameters().nominal_values();
  VectorXd q(model->mechanism().num_actuators());
  const InverseKinematicsResult ik = model->mechanism().inverse_kinematics(
      params.head(model->mechanism().num_parameters()), pose, q);
  if (!ik.ok())
    throw CliError("--pose '" + vm["pose"].as<std::string>() + "': inverse kinematics " +
                   ik.describe() + "; expected a pose the model can reach");
  VectorXd readings(model->num_readings());
  model->predict_at_pose(params, pose, readings);
  // Finite input can still overflow (1e308 squared): say so instead of printing inf.
  if (!q.allFinite() || !readings.allFinite())
    throw CliError("--pose '" + vm["pose"].as<std::string>() +
                   "': the actuator values or readings at this pose are not finite numbers (the "
                   "arithmetic overflows); expected a pose near the machine's workspace");
  const auto& names = model->mechanism().actuator_names();
  // Micrometres for lengths; for angles nanoradians, a micrometre at a metre's reach.
  const auto& actuators = model->mechanism().actuators();
  for (int i = 0; i < q.size(); ++i)
    std::printf(actuators[i].unit == kRadian ? "%-8s %.9f\n" : "%-8s %.6f\n", names[i].c_str(),
                q[i]);
  const auto reading_names = model->reading_names();
  for (int k = 0; k < readings.size(); ++k)
    std::printf("%-8s %.6f\n", reading_names[k].c_str(), readings[k]);
  return 0;
}

}  // namespace kincal::cli
