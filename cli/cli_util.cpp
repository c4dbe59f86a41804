#include "cli/cli_util.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>

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

void ensure_directory(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir))
    throw CliError("cannot create directory '" + dir + "'" +
                   (ec ? ": " + ec.message() : std::string()));
}

}  // namespace kincal::cli
