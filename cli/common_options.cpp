#include "kincal/cli/common_options.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "kincal/framework/least_squares/solver_registry.hpp"

#include "kincal/cli/console.hpp"

#ifndef KINCAL_VERSION
#define KINCAL_VERSION "unknown"
#endif
#ifndef KINCAL_GIT_DESCRIBE
#define KINCAL_GIT_DESCRIBE ""
#endif

namespace kincal::cli {

void add_json_option(po::options_description& options, const std::string& what) {
  options.add_options()("json", po::value<std::string>(),
                        ("write " + what + " as JSON to FILE, or - for standard output").c_str());
}

std::string json_output(const po::variables_map& vm) {
  return vm.count("json") ? vm["json"].as<std::string>() : "";
}

void add_progress_option(po::options_description& options) {
  options.add_options()("progress", po::bool_switch(),
                        "show progress with the time remaining on stderr (shown anyway when "
                        "stderr is a terminal)");
}

bool progress_wanted(const po::variables_map& vm) {
  return (vm.count("progress") && vm["progress"].as<bool>()) ||
         (err_is_process_stderr() && ::isatty(STDERR_FILENO));
}

std::string default_text(double value) {
  char text[40];
  // Whole numbers as such: %.1g would write 200 as 2e+02.
  if (value == std::floor(value) && std::fabs(value) < 1e15) {
    std::snprintf(text, sizeof text, "%.0f", value);
    return text;
  }
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, value);
    if (std::strtod(text, nullptr) == value) break;
  }
  return text;
}

std::string version_text() {
  std::string text = std::string("kincal ") + KINCAL_VERSION;
  const std::string git = KINCAL_GIT_DESCRIBE;
  if (!git.empty()) text += " (git " + git + ")";
  text += "\nsolver backends:";
  for (const auto& info : SolverRegistry::global().list()) text += " " + info.name;
  for (const auto& missing : SolverRegistry::global().unavailable())
    text += "\nnot in this build: " + missing.name + " (" + missing.reason + ")";
  return text + "\n";
}

nlohmann::ordered_json json_document(const std::string& format, int version) {
  return {{"format", format}, {"version", version}};
}

}  // namespace kincal::cli
