// kincal export: a calibrated model in a form a controller or robot description takes
// (URDF for serial arms, a joint-coordinate CSV, plain JSON); cli/export_formats.hpp.

#include <nlohmann/json.hpp>

#include "kincal/cli/export_formats.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/cli/sha256.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/framework/io/json_input.hpp"

namespace kincal::cli {

int run_export(const Args& args) {
  po::options_description options("kincal export");
  options.add_options()("model", po::value<std::string>(), "model file (JSON), e.g. calibrated")(
      "format", po::value<std::string>(),
      "urdf (serial arms), csv, json, or one a plug-in registers")(
      "out", po::value<std::string>()->default_value("-"), "file to write, - for stdout");
  po::variables_map vm;
  if (!parse_command_line("export", args, options, vm)) return 0;
  if (!vm.count("model")) throw CliError("--model FILE is required");
  if (!vm.count("format")) throw CliError("--format urdf|csv|json is required");
  const std::string format = vm["format"].as<std::string>();
  OutputPlan plan;
  plan.input("--model", vm["model"].as<std::string>());
  plan.output("--out", vm["out"].as<std::string>());
  plan.check();

  const std::shared_ptr<MeasurementModel> model = load_model_option(vm);
  // Formats beyond kincal's own are registered per mechanism type (a plug-in's).
  const ModelRegistry& registry = ModelRegistry::global();
  const std::string& type = model->mechanism().type();
  const ExportFormat* registered = registry.export_format(type, format);
  if (format != "urdf" && format != "csv" && format != "json" && !registered) {
    std::string known = "urdf, csv, json";
    for (const auto& f : registry.export_formats())
      if (f.mechanism_type == type) known += ", " + f.format;
    throw CliError("--format '" + format + "': expected " + known + " for mechanism '" + type +
                   "'");
  }
  ExportSource source;
  source.model_file = vm["model"].as<std::string>();
  source.sha256 = model_file_sha256(source.model_file);
  std::string text;
  try {
    text = registered         ? registered->write(*model, {source.model_file, source.sha256})
           : format == "urdf" ? export_urdf(*model, source)
           : format == "csv"  ? export_csv(*model, source)
                              : export_json(*model, source);
  } catch (const ExportError& e) {
    throw CliError(source.model_file + ": " + e.what());
  } catch (const std::invalid_argument& e) {
    throw CliError(source.model_file + ": --format " + format + ": " + e.what());
  } catch (const nlohmann::json::exception& e) {
    throw CliError(source.model_file + ": cannot be written as JSON (" + e.what() + ")");
  }
  plan.write({{"--out", text}});
  return 0;
}

}  // namespace kincal::cli
