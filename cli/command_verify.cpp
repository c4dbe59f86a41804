// kincal verify: whether a calibrated model file is the one a calibration report was
// written with. calibrate writes the two files one after the other, so a crash between the
// two renames can leave a new report beside an old model; the report records the SHA-256
// of its model, and this command compares it.

#include <iostream>
#include <stdexcept>

#include "kincal/cli/cli_util.hpp"
#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/io/json_input.hpp"
#include "kincal/framework/io/sha256.hpp"
#include "kincal/framework/workflows/report_prediction.hpp"

namespace kincal::cli {

int run_verify(const Args& args) {
  po::options_description options("kincal verify");
  options.add_options()("report", po::value<std::string>(), "calibration report (JSON)")(
      "model", po::value<std::string>(),
      "calibrated model file to check (default: the file the report names, as calibrate was "
      "given it)");
  add_json_option(options, "the verdict");
  po::variables_map vm;
  if (!parse_command_line("verify", args, options, vm)) return 0;
  if (!vm.count("report")) throw CliError("--report FILE is required");
  const std::string report_file = vm["report"].as<std::string>();
  OutputPlan plan(console_output());  // no outputs; standard output must not be an input
  plan.input("--report", report_file);
  if (vm.count("model")) plan.input("--model", vm["model"].as<std::string>());
  const std::string json_file = json_output(vm);
  if (!json_file.empty()) plan.output("--json", json_file);
  plan.check();
  const bool json_to_stdout = !json_file.empty() && plan.to_stdout("--json");

  JsonLimits limits;  // a report lists every residual: as large as validate reads
  limits.max_bytes = kMaxCalibrationReportBytes;
  const nlohmann::ordered_json report = read_json_file(report_file, "calibration report", limits);
  if (!report.is_object() || report.value("format", "") != "kincal-calibration-report")
    throw CliError(report_file +
                   ": expected a calibration report (format "
                   "\"kincal-calibration-report\")");
  const auto entry = report.find("calibrated_model");
  if (entry == report.end() || entry->is_null())
    throw CliError(report_file +
                   ": names no calibrated model (calibrate ran without --out, or its solver "
                   "did not reach a solution); nothing to check");
  if (!entry->is_object() || !entry->contains("file") || !(*entry)["file"].is_string() ||
      !entry->contains("sha256") || !(*entry)["sha256"].is_string())
    throw CliError(report_file + ": calibrated_model: expected {\"file\": ..., \"sha256\": ...}");
  const std::string model_file =
      vm.count("model") ? vm["model"].as<std::string>() : (*entry)["file"].get<std::string>();
  const std::string expected = (*entry)["sha256"].get<std::string>();
  const std::string actual = model_file_sha256(model_file);
  if (!json_file.empty()) {
    const nlohmann::ordered_json verdict = {{"format", "kincal-verify"},   {"version", 1},
                                            {"report", report_file},       {"model", model_file},
                                            {"match", actual == expected}, {"sha256", actual},
                                            {"expected_sha256", expected}};
    plan.write({{"--json", verdict.dump(2) + "\n"}});
  }
  if (actual != expected) {
    err() << "kincal verify: error: " << model_file << " is not the model " << report_file
          << " describes: its SHA-256 is " << actual << ", the report's " << expected
          << " (a calibrate interrupted between writing the two leaves a new report beside "
             "an old model; run it again)\n";
    return 1;
  }
  if (json_to_stdout) return 0;
  out() << printable(model_file) << " is the calibrated model " << printable(report_file)
        << " describes (SHA-256 " << actual << ")\n";
  return 0;
}

}  // namespace kincal::cli
