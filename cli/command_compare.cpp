// kincal compare: a model (a calibration's result) against a known truth (a simulation's
// <stem>.truth.json): the error of each parameter, and the error of the mechanism's pose over
// a set of configurations, in text, JSON and HTML. Closes the design loop: design ->
// simulate --configs -> calibrate -> compare.

#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/cli/project_record.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/calibration/measurement_file.hpp"
#include "kincal/framework/kinematics/model_pair.hpp"
#include "kincal/framework/report/pages.hpp"
#include "kincal/framework/workflows/compare.hpp"

namespace kincal::cli {

int run_compare(const Args& args) {
  po::options_description options("kincal compare");
  options.add_options()("truth", po::value<std::string>(),
                        "the true model (a model file, e.g. simulate --write-data's "
                        "<stem>.truth.json)")(
      "model", po::value<std::string>(),
      "the model to judge (e.g. calibrate --out's), with the same parameters as --truth")(
      "data", po::value<std::string>(),
      "compare the poses at the configurations of this measurement file (its actuator "
      "columns; readings are not used) instead of a sample of the workspace")(
      "poses", po::value<int>()->default_value(200),
      "workspace configurations drawn in the truth's actuator box (without --data)")(
      "seed", po::value<Seed>()->default_value(Seed{1}, "1"),
      "random seed of the workspace sample")(
      "html", po::value<std::string>(),
      "write the comparison for people to FILE: one self-contained HTML page");
  add_json_option(options, "the comparison");
  add_data_size_option(options);
  po::variables_map vm;
  if (!parse_command_line("compare", args, options, vm)) return 0;
  if (!vm.count("truth")) throw CliError("--truth FILE is required (the true model)");
  if (!vm.count("model")) throw CliError("--model FILE is required (the model to judge)");
  const int poses = vm["poses"].as<int>();
  if (vm.count("data") && !vm["poses"].defaulted())
    throw CliError("--data gives the configurations: give it without --poses");
  if (poses < 1) throw CliError("--poses must be at least 1");
  if (poses > 1000000) throw CliError("--poses must be at most 1000000");
  OutputPlan plan(console_output());
  for (const char* option : {"truth", "model", "data"})
    if (vm.count(option)) plan.input(std::string("--") + option, vm[option].as<std::string>());
  const std::string json_file = json_output(vm);
  if (!json_file.empty()) plan.output("--json", json_file);
  if (vm.count("html")) plan.output("--html", vm["html"].as<std::string>());
  plan.check();

  CompareRequest request;
  request.truth_file = vm["truth"].as<std::string>();
  request.model_file = vm["model"].as<std::string>();
  request.truth = load_model_file(request.truth_file);
  const std::shared_ptr<MeasurementModel> model = load_model_option(vm);
  request.model = model;
  check_same_parameters(*request.truth, "--truth " + printable(request.truth_file), *model,
                        "--model " + printable(request.model_file));
  // Configurations: --data's actuator columns, or a sample of the truth's workspace.
  if (vm.count("data")) {
    request.data_file = vm["data"].as<std::string>();
    try {
      request.configurations =
          read_model_columns(request.data_file, *model, data_limits(vm)).data.actuators;
    } catch (const std::invalid_argument& e) {
      throw measurement_file_error(e);
    }
  }
  request.workspace_poses = poses;
  request.seed = vm["seed"].as<Seed>().value;
  const CompareResult result = compare_models(request);
  const bool quiet = (!json_file.empty() && plan.to_stdout("--json")) ||
                     (vm.count("html") && plan.to_stdout("--html"));
  if (!quiet) out() << comparison_text(result);
  const nlohmann::ordered_json j = comparison_json(result);
  std::vector<std::pair<std::string, std::string>> outputs;
  if (!json_file.empty()) outputs.push_back({"--json", json_report_text(j)});
  if (vm.count("html")) outputs.push_back({"--html", report::compare_html(result)});
  plan.write(outputs);
  return 0;
}

}  // namespace kincal::cli
