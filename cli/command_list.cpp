// kincal list: what this build has: solver backends, preset models, mechanism, sensor and
// constraint types. One line each, name first, and the plug-in file for what a plug-in added; with
// --json the same as one object.

#include <iostream>
#include <nlohmann/json.hpp>

#include "kincal/cli/cli_util.hpp"
#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/plugin_option.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/framework/extension/plugin.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"

namespace kincal::cli {

namespace {

constexpr const char* kUsage =
    "usage: kincal list [solvers|models|mechanisms|sensors|constraints] [--json FILE|-]   "
    "(everything when no section is given)";

struct Entry {
  std::string name;
  std::string description;
  std::string plugin;  ///< the plug-in file that added it; empty when built in
};
using Entries = std::vector<Entry>;

Entries solvers() {
  Entries out;
  for (const auto& info : SolverRegistry::global().list())
    out.push_back({info.name, info.description, plugin_providing("solver", info.name)});
  // Backends left out of this build, so that a missing one is not a mystery.
  for (const auto& missing : SolverRegistry::global().unavailable())
    out.push_back({missing.name, "not in this build: " + missing.reason, ""});
  return out;
}

Entries models() {
  Entries out;
  for (const auto& preset : ModelRegistry::global().presets())
    out.push_back({preset.name, preset.description, plugin_providing("preset", preset.name)});
  return out;
}

Entries mechanisms() {
  Entries out;
  for (const auto& type : ModelRegistry::global().mechanisms())
    out.push_back({type.type, type.description, plugin_providing("mechanism type", type.type)});
  return out;
}

Entries constraints() {
  Entries out;
  for (const auto& type : ModelRegistry::global().constraints())
    out.push_back({type.type, type.description, plugin_providing("constraint type", type.type)});
  return out;
}

Entries sensors() {
  Entries out;
  for (const auto& type : ModelRegistry::global().sensors())
    out.push_back({type.type, type.description, plugin_providing("sensor type", type.type)});
  return out;
}

// Escaped (control characters and bytes that are not UTF-8 as \xNN): a plug-in's names and
// descriptions are checked when it is loaded, and its file name is the user's.
void print(const Entries& entries) {
  for (const auto& e : entries) {
    std::string padded = printable(e.name);
    if (padded.size() < 22) padded.resize(22, ' ');
    out() << padded << " " << printable(e.description);
    if (!e.plugin.empty()) out() << " [plug-in " << printable(e.plugin) << "]";
    out() << "\n";
  }
}

nlohmann::json to_json(const Entries& entries, bool solvers) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& entry : entries) {
    nlohmann::json e = {{"name", entry.name}, {"description", entry.description}};
    if (solvers) e["available"] = entry.description.rfind("not in this build: ", 0) != 0;
    e["plugin"] = entry.plugin.empty() ? nlohmann::json() : nlohmann::json(entry.plugin);
    out.push_back(e);
  }
  return out;
}

}  // namespace

int run_list(const Args& args) {
  po::options_description options("kincal list");
  std::string what;
  options.add_options()("what", po::value<std::string>(&what),
                        "solvers, models (presets), mechanisms, sensors or constraints; all when "
                        "omitted");
  add_json_option(options, "the list");
  add_plugin_option(options);
  options.add_options()("help,h", "show this help")("version", "show kincal's version and exit");
  po::positional_options_description positional;
  positional.add("what", 1);
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(args).options(options).positional(positional).run(), vm);
    load_plugins(vm);  // after the parse: only a real --plugin option names one
    if (vm.count("help")) {
      out() << kUsage << "\n" << options << "\n";
      return 0;
    }
    if (vm.count("version")) {
      out() << version_text();
      return 0;
    }
    po::notify(vm);
  } catch (const po::error& e) {
    throw CliError(option_error_message(e, args, options) + " (" + kUsage + ")");
  }
  const std::vector<std::pair<std::string, Entries (*)()>> sections = {
      {"solvers", solvers},
      {"models", models},
      {"mechanisms", mechanisms},
      {"sensors", sensors},
      {"constraints", constraints}};
  bool known = what.empty();
  for (const auto& section : sections) known = known || what == section.first;
  if (!known)
    throw CliError("cannot list '" + what +
                   "' (expected solvers, models, mechanisms, sensors or constraints)");
  const std::string json_file = json_output(vm);
  OutputPlan plan(console_output());
  if (!json_file.empty()) plan.output("--json", json_file);
  plan.check();
  const bool json_to_stdout = !json_file.empty() && plan.to_stdout("--json");
  nlohmann::ordered_json json = json_document("kincal-list");
  bool first = true;
  for (const auto& [name, list] : sections) {
    if (!what.empty() && what != name) continue;
    const Entries entries = list();
    json[name] = to_json(entries, name == "solvers");
    if (json_to_stdout) continue;
    if (what.empty()) out() << (first ? "" : "\n") << name << ":\n";
    print(entries);
    first = false;
  }
  if (!json_file.empty()) plan.write({{"--json", json.dump(2) + "\n"}});
  return 0;
}

}  // namespace kincal::cli
