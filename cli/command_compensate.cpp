// kincal compensate: corrected targets for the controller. The commands that make a calibrated
// model read what is wanted (framework/workflows/compensate.hpp): geometry and joint
// deflection under gravity and payload included.

#include <algorithm>

#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/cli/project_record.hpp"
#include "kincal/framework/workflows/compensate.hpp"

namespace kincal::cli {

int run_compensate(const Args& args) {
  po::options_description options("kincal compensate");
  options.add_options()("model", po::value<std::string>(), "the calibrated model file (JSON)")(
      "targets", po::value<std::string>(),
      "CSV: the wanted readings (the model's reading columns, e.g. tracker.x,tracker.y,"
      "tracker.z in the measurement frame) and, optionally, the commands each row starts from "
      "(all commanded actuator columns)")(
      "nominal", po::value<std::string>(),
      "a nominal model file: --targets gives commands only, and the wanted readings are what "
      "this model predicts at them (commands planned with the controller's kinematics)")(
      "near", po::value<std::string>(),
      "q1,q2,...: the configuration rows without commands start from (default: home), in the "
      "actuators' units")(
      "payload", po::value<double>(),
      "kg: the payload's mass where --targets has no payload column (models with a payload "
      "column)")("tolerance", po::value<double>()->default_value(1e-9),
                 "solved when every reading is within this of the wanted one (the readings' unit)")(
      "out", po::value<std::string>(), "CSV of the compensated commands (- for stdout)");
  add_json_option(options, "the summary");
  po::variables_map vm;
  if (!parse_command_line("compensate", args, options, vm)) return 0;
  OutputPlan plan(console_output());
  if (!vm.count("model")) throw CliError("--model FILE is required");
  if (!vm.count("targets")) throw CliError("--targets FILE is required");
  plan.input("--model", vm["model"].as<std::string>());
  plan.input("--targets", vm["targets"].as<std::string>());
  if (vm.count("nominal")) plan.input("--nominal", vm["nominal"].as<std::string>());
  if (!vm.count("out")) throw CliError("--out FILE is required (the compensated commands)");
  plan.output("--out", vm["out"].as<std::string>());
  const std::string json_file = json_output(vm);
  if (!json_file.empty()) plan.output("--json", json_file);
  plan.check();
  const auto model = load_model_option(vm);
  std::shared_ptr<MeasurementModel> nominal;
  if (vm.count("nominal")) nominal = load_model_file(vm["nominal"].as<std::string>());
  VectorXd near;
  if (vm.count("near")) {
    const int na = model->mechanism().num_actuators();
    const auto v = parse_numbers(vm["near"].as<std::string>(), na, "near",
                                 "one value per actuator, in its unit");
    near = Eigen::Map<const VectorXd>(v.data(), na);
  }
  std::vector<std::pair<std::string, double>> inputs;
  if (vm.count("payload")) {
    const auto names = model->mechanism().actuator_names();
    if (std::find(names.begin(), names.end(), "payload") == names.end())
      throw CliError("--payload: the model has no payload column (kincal model --payload-column)");
    const double payload = vm["payload"].as<double>();
    if (!(payload >= 0)) throw CliError("--payload: expected a mass >= 0 kg");
    inputs.emplace_back("payload", payload);
  }
  const double tolerance = vm["tolerance"].as<double>();
  if (!(tolerance > 0)) throw CliError("--tolerance: expected a value > 0");
  CompensateRequest request;
  request.model = model;
  request.tolerance = tolerance;
  try {
    request.targets = read_compensate_targets(vm["targets"].as<std::string>(), *model,
                                              nominal.get(), near, inputs);
  } catch (const std::invalid_argument& e) {
    throw CliError(e.what());
  }
  const CompensateResult result = compensate(request);
  std::vector<std::pair<std::string, std::string>> contents = {
      {"--out", compensated_csv(*model, result)}};
  if (!json_file.empty()) {
    nlohmann::ordered_json json = compensate_json(*model, result);
    json["model"] = vm["model"].as<std::string>();
    json["targets"] = vm["targets"].as<std::string>();
    contents.emplace_back("--json", json_report_text(json));
  }
  plan.write(contents);
  if (!plan.to_stdout("--out") && (json_file.empty() || !plan.to_stdout("--json")))
    out() << compensate_text(*model, result);
  return result.failed > 0 ? 1 : 0;
}

}  // namespace kincal::cli
