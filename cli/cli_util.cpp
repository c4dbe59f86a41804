#include "cli/cli_util.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>

#include "framework/solver_registry.hpp"

namespace kincal::cli {

bool parse_command_line(const std::string& command, const Args& args,
                        po::options_description& options, po::variables_map& vm) {
  options.add_options()("help,h", "show this help");
  try {
    po::store(po::command_line_parser(args).options(options).run(), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    throw CliError(e.what());
  }
  if (vm.count("help")) {
    std::cout << "usage: kincal " << command << " [options]\n" << options << "\n";
    return false;
  }
  return true;
}

std::map<std::string, std::string> parse_key_values(const std::vector<std::string>& entries,
                                                    const std::string& option_name) {
  std::map<std::string, std::string> out;
  for (const auto& entry : entries) {
    const auto eq = entry.find('=');
    if (eq == std::string::npos || eq == 0)
      throw CliError("--" + option_name + " '" + entry + "': expected key=value");
    out[entry.substr(0, eq)] = entry.substr(eq + 1);
  }
  return out;
}

void write_file_atomically(const std::string& path, const std::string& content) {
  if (path == "-") {
    std::cout << content;
    std::cout.flush();
    return;
  }
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  // Unique temporary name beside the target so the rename stays on one file system.
  std::random_device rd;
  const fs::path temp =
      dir / ("." + target.filename().string() + ".tmp" + std::to_string(rd() % 1000000));
  {
    std::ofstream out(temp, std::ios::binary);
    if (!out) throw CliError("cannot write '" + path + "': directory missing or not writable");
    out << content;
    out.close();
    if (!out) {
      std::error_code ec;
      fs::remove(temp, ec);
      throw CliError("cannot write '" + path + "': write failed (disk full?)");
    }
  }
  std::error_code ec;
  fs::rename(temp, target, ec);
  if (ec) {
    fs::remove(temp, ec);
    throw CliError("cannot write '" + path + "': " + ec.message());
  }
}

std::string default_solver_name() { return SolverRegistry::global().contains("lm") ? "lm" : "gn"; }

void add_solver_options(po::options_description& options) {
  options.add_options()("solver", po::value<std::string>()->default_value(default_solver_name()),
                        "solver backend (kincal list solvers)")(
      "solver-option", po::value<std::vector<std::string>>()->composing(),
      "backend-specific setting key=value (repeatable; see docs/solvers.md)")(
      "max-iterations", po::value<int>()->default_value(100), "iteration limit of the solver")(
      "verbose,v", po::bool_switch(), "print one line per solver iteration on stderr");
}

SolverChoice make_solver_choice(const po::variables_map& vm) {
  SolverChoice choice;
  choice.name = vm["solver"].as<std::string>();
  try {
    choice.solver = SolverRegistry::global().create(choice.name);
    if (vm.count("solver-option"))
      choice.options.backend_options =
          parse_key_values(vm["solver-option"].as<std::vector<std::string>>(), "solver-option");
    choice.options.max_iterations = vm["max-iterations"].as<int>();
    if (choice.options.max_iterations < 0) throw CliError("--max-iterations must be >= 0");
    choice.options.verbosity = vm["verbose"].as<bool>() ? 1 : 0;
    choice.solver->check_options(choice.options);
  } catch (const InvalidSolverOptions& e) {
    throw CliError(e.what());
  }
  return choice;
}

void ensure_directory(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir))
    throw CliError("cannot create directory '" + dir + "'" +
                   (ec ? ": " + ec.message() : std::string()));
}

}  // namespace kincal::cli
