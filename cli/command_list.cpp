// kincal list: what this build has: solver backends, preset models, mechanism and sensor
// types. One line each, name first.

#include <iostream>

#include "kincal/cli/cli_util.hpp"
#include "kincal/framework/model_registry.hpp"
#include "kincal/framework/solver_registry.hpp"

namespace kincal::cli {

namespace {

constexpr const char* kUsage = "usage: kincal list [solvers|models|mechanisms|sensors]";

void line(const std::string& name, const std::string& text) {
  std::string padded = name;
  if (padded.size() < 22) padded.resize(22, ' ');
  std::cout << padded << " " << text << "\n";
}

void list_solvers() {
  for (const auto& info : SolverRegistry::global().list()) line(info.name, info.description);
  // Backends left out of this build, so that a missing one is not a mystery.
  for (const auto& missing : SolverRegistry::global().unavailable())
    line(missing.name, "not in this build: " + missing.reason);
}

void list_models() {
  for (const auto& preset : ModelRegistry::global().presets())
    line(preset.name, preset.description);
}

void list_mechanisms() {
  for (const auto& type : ModelRegistry::global().mechanisms()) line(type.type, type.description);
}

void list_sensors() {
  for (const auto& type : ModelRegistry::global().sensors()) line(type.type, type.description);
}

}  // namespace

int run_list(const Args& args) {
  po::options_description options("kincal list");
  std::string what;
  options.add_options()("what", po::value<std::string>(&what),
                        "solvers, models (presets), mechanisms or sensors; all when omitted")(
      "help,h", "show this help");
  po::positional_options_description positional;
  positional.add("what", 1);
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(args).options(options).positional(positional).run(), vm);
    if (vm.count("help")) {
      std::cout << kUsage << "\n";
      return 0;
    }
    po::notify(vm);
  } catch (const po::error& e) {
    throw CliError(option_error_message(e, args) + " (" + kUsage + ")");
  }
  const std::vector<std::pair<const char*, void (*)()>> sections = {{"solvers", list_solvers},
                                                                    {"models", list_models},
                                                                    {"mechanisms", list_mechanisms},
                                                                    {"sensors", list_sensors}};
  if (what.empty()) {
    for (std::size_t i = 0; i < sections.size(); ++i) {
      std::cout << (i ? "\n" : "") << sections[i].first << ":\n";
      sections[i].second();
    }
    return 0;
  }
  for (const auto& [name, print] : sections)
    if (what == name) {
      print();
      return 0;
    }
  throw CliError("cannot list '" + what + "' (expected solvers, models, mechanisms or sensors)");
}

}  // namespace kincal::cli
