// kincal check: the conformance checks of the test suite (models/conformance.hpp) on any
// preset or model file, including a plug-in's: a plug-in author's test, with no test code.
// One verdict line per check with its worst error; exit 1 when a check fails.

#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/cli/project_record.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/conformance.hpp"

namespace kincal::cli {

namespace {

struct Subject {
  std::string label;  ///< "preset five-bar-demo", "model arm.json"
  ModelFactory make;
};

// The presets not built in: those of the loaded plug-ins (or of the program that runs
// kincal::cli::run with its own types).
std::vector<std::string> added_presets() {
  ModelRegistry builtin;
  register_builtin_models(builtin);
  std::vector<std::string> out;
  for (const auto& p : ModelRegistry::global().presets()) {
    bool known = false;
    for (const auto& b : builtin.presets()) known = known || b.name == p.name;
    if (!known) out.push_back(p.name);
  }
  return out;
}

std::string number(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2g", value);
  return buf;
}

}  // namespace

int run_check(const Args& args) {
  po::options_description options("kincal check");
  options.add_options()("preset", po::value<std::vector<std::string>>(),
                        "check this preset (repeatable)")("model", po::value<std::string>(),
                                                          "check the model in this file (JSON)")(
      "all", po::bool_switch(), "check every preset, and that every type is in one");
  add_json_option(options, "the verdicts");
  po::variables_map vm;
  if (!parse_command_line("check", args, options, vm)) return 0;
  const int selections = static_cast<int>(vm.count("preset") > 0) +
                         static_cast<int>(vm.count("model") > 0) +
                         static_cast<int>(vm["all"].as<bool>());
  if (selections > 1) throw CliError("give one of --preset, --model and --all");
  const std::string json_file = json_output(vm);
  OutputPlan plan(console_output());
  if (vm.count("model")) plan.input("--model", vm["model"].as<std::string>());
  if (!json_file.empty()) plan.output("--json", json_file);
  plan.check();

  std::vector<Subject> subjects;
  const ModelRegistry& registry = ModelRegistry::global();
  std::vector<std::string> presets;
  if (vm.count("preset")) {
    presets = vm["preset"].as<std::vector<std::string>>();
    for (const auto& name : presets) registry.preset(name);  // an unknown name fails here
  } else if (vm["all"].as<bool>()) {
    for (const auto& p : registry.presets()) presets.push_back(p.name);
  } else if (!vm.count("model")) {
    presets = added_presets();
    if (presets.empty())
      throw CliError(
          "nothing to check: give --preset NAME, --model FILE or --all (without them, check "
          "takes the presets of the plug-ins given with --plugin, and none is loaded)");
  }
  for (const auto& name : presets)
    subjects.push_back(
        {"preset " + name, [&registry, name] { return registry.make_preset(name); }});
  if (vm.count("model")) {
    const std::string path = vm["model"].as<std::string>();
    load_model_file(path);  // bad input is an error before any check runs
    subjects.push_back({"model " + path, [path] { return load_model_file(path); }});
  }

  const bool json_to_stdout = !json_file.empty() && plan.to_stdout("--json");
  nlohmann::ordered_json json = json_document("kincal-check");
  json["subjects"] = nlohmann::ordered_json::array();
  int failures = 0, total = 0;
  auto report = [&](const std::string& label, const std::vector<ConformanceCheck>& checks) {
    nlohmann::ordered_json entry = {{"subject", label},
                                    {"checks", nlohmann::ordered_json::array()}};
    for (const auto& c : checks) {
      ++total;
      failures += c.passed ? 0 : 1;
      entry["checks"].push_back({{"check", c.name},
                                 {"passed", c.passed},
                                 {"worst", std::isnan(c.worst) ? nlohmann::ordered_json()
                                                               : nlohmann::ordered_json(c.worst)},
                                 {"tolerance", c.tolerance},
                                 {"detail", c.detail}});
      if (json_to_stdout) continue;
      std::string line = std::string(c.passed ? "pass" : "FAIL") + "  " + label + ": " + c.name;
      if (c.tolerance > 0)
        line += "  worst " + number(c.worst) + " (tolerance " + number(c.tolerance) + ")";
      if (!c.detail.empty()) line += "  " + c.detail;
      out() << line << std::endl;
    }
    json["subjects"].push_back(entry);
  };
  if (vm["all"].as<bool>()) report("registry", check_registry_coverage(registry));
  for (const auto& subject : subjects)
    report(subject.label, check_model(subject.make, SolverRegistry::global()));
  json["checks"] = total;
  json["failures"] = failures;
  if (!json_to_stdout)
    out() << (failures ? "FAILED: " + std::to_string(failures) + " of " : "passed: all ") << total
          << " checks\n";
  if (!json_file.empty()) plan.write({{"--json", json_report_text(json)}});
  return failures ? 1 : 0;
}

}  // namespace kincal::cli
