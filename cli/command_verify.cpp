// kincal verify: whether a calibrated model file is the one a calibration report was
// written with (framework/workflows/verify.hpp).

#include <iostream>
#include <stdexcept>

#include "kincal/cli/cli_util.hpp"
#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/project_record.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/workflows/verify.hpp"

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

  const VerifyResult result = verify_calibration(
      report_file, vm.count("model") ? vm["model"].as<std::string>() : std::string());
  if (!json_file.empty()) plan.write({{"--json", json_report_text(verify_json(result))}});
  if (!result.match) {
    err() << "kincal verify: error: " << verify_mismatch_text(result) << "\n";
    return 1;
  }
  if (json_to_stdout) return 0;
  out() << printable(result.model_file) << " is the calibrated model " << printable(report_file)
        << " describes (SHA-256 " << result.sha256 << ")\n";
  return 0;
}

}  // namespace kincal::cli
