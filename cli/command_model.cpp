// kincal model: writes a built-in model as a model file for users to edit.

#include "kincal/cli/model_args.hpp"
#include "kincal/models/model_io.hpp"
#include "kincal/models/presets.hpp"

namespace kincal::cli {

int run_model(const Args& args) {
  po::options_description options("kincal model");
  options.add_options()("preset", po::value<std::string>()->default_value("cube-hexapod"),
                        "built-in model (kincal list models)")(
      "out", po::value<std::string>()->default_value("-"), "model file to write, - for stdout");
  add_free_fix_options(options);
  po::variables_map vm;
  if (!parse_command_line("model", args, options, vm)) return 0;
  std::shared_ptr<MeasurementModel> model;
  try {
    model = make_preset(vm["preset"].as<std::string>());
  } catch (const std::invalid_argument& e) {
    throw CliError(std::string("--preset: ") + e.what());
  }
  apply_free_fix(vm, *model);
  OutputPlan plan;
  plan.output("--out", vm["out"].as<std::string>());
  plan.check();
  plan.write(
      {{"--out", model_to_json(*model, model->parameters().nominal_values()).dump(2) + "\n"}});
  return 0;
}

}  // namespace kincal::cli
