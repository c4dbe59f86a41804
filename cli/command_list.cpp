#include <iostream>

#include "kincal/cli/cli_util.hpp"
#include "kincal/framework/solver_registry.hpp"
#include "kincal/models/presets.hpp"

namespace kincal::cli {

int run_list(const Args& args) {
  po::options_description options("kincal list solvers|models");
  std::string what;
  options.add_options()("what", po::value<std::string>(&what)->required(), "solvers or models");
  po::positional_options_description positional;
  positional.add("what", 1);
  po::variables_map vm;
  options.add_options()("help,h", "show this help");
  try {
    po::store(po::command_line_parser(args).options(options).positional(positional).run(), vm);
    if (vm.count("help")) {
      std::cout << "usage: kincal list solvers|models\n";
      return 0;
    }
    po::notify(vm);
  } catch (const po::error& e) {
    throw CliError(option_error_message(e, args) + " (usage: kincal list solvers|models)");
  }
  if (what == "solvers") {
    for (const auto& info : SolverRegistry::global().list()) {
      std::string name = info.name;
      if (name.size() < 22) name.resize(22, ' ');
      std::cout << name << " " << info.description << "\n";
    }
    // Backends left out of this build, so that a missing one is not a mystery.
    for (const auto& missing : SolverRegistry::global().unavailable()) {
      std::string name = missing.name;
      if (name.size() < 22) name.resize(22, ' ');
      std::cout << name << " not in this build: " << missing.reason << "\n";
    }
  } else if (what == "models") {
    for (const auto& preset : list_presets()) {
      std::string name = preset.name;
      if (name.size() < 22) name.resize(22, ' ');
      std::cout << name << " " << preset.description << "\n";
    }
  } else {
    throw CliError("cannot list '" + what + "' (expected solvers or models)");
  }
  return 0;
}

}  // namespace kincal::cli
