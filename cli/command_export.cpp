// kincal export: a calibrated model in a form a controller or robot description takes
// (URDF for serial arms, a joint-coordinate CSV, plain JSON); cli/export_formats.hpp.

#include <nlohmann/json.hpp>

#include "kincal/cli/console.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/framework/io/json_input.hpp"
#include "kincal/framework/io/sha256.hpp"
#include "kincal/models/export_formats.hpp"

namespace kincal::cli {

int run_export(const Args& args) {
  po::options_description options("kincal export");
  options.add_options()("model", po::value<std::string>(), "model file (JSON), e.g. calibrated")(
      "format", po::value<std::string>(),
      "urdf (serial arms), csv, json, camera-info (a camera's intrinsics as ROS camera_info "
      "YAML), or one a plug-in registers")("out", po::value<std::string>()->default_value("-"),
                                           "file to write, - for stdout");
  po::variables_map vm;
  if (!parse_command_line("export", args, options, vm)) return 0;
  if (!vm.count("model")) throw CliError("--model FILE is required");
  if (!vm.count("format")) throw CliError("--format urdf|csv|json|camera-info is required");
  const std::string format = vm["format"].as<std::string>();
  OutputPlan plan(console_output());
  plan.input("--model", vm["model"].as<std::string>());
  plan.output("--out", vm["out"].as<std::string>());
  plan.check();

  const std::shared_ptr<MeasurementModel> model = load_model_option(vm);
  ExportSource source;
  source.model_file = vm["model"].as<std::string>();
  source.sha256 = model_file_sha256(source.model_file);
  std::string text;
  try {
    text = export_model(*model, format, source);
  } catch (const ExportError& e) {
    throw CliError(source.model_file + ": " + e.what());
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    if (what.rfind("format '", 0) == 0) throw CliError("--" + what);  // an unknown format
    throw CliError(source.model_file + ": --format " + format + ": " + what);
  } catch (const nlohmann::json::exception& e) {
    throw CliError(source.model_file + ": cannot be written as JSON (" + e.what() + ")");
  }
  plan.write({{"--out", text}});
  return 0;
}

}  // namespace kincal::cli
