#include "kincal/cli/plugin_option.hpp"

#include <string>
#include <vector>

#include "kincal/cli/commands.hpp"
#include "kincal/framework/extension/plugin.hpp"

namespace kincal::cli {

void add_plugin_option(boost::program_options::options_description& options) {
  options.add_options()("plugin", boost::program_options::value<std::vector<std::string>>(),
                        "load this kincal plug-in (a shared library with further mechanism, "
                        "sensor and solver types; repeatable), after those KINCAL_PLUGIN_PATH "
                        "names (files or folders, ':' between them)");
}

void load_plugins(const boost::program_options::variables_map& vm) {
  std::vector<std::string> files = plugins_from_environment();
  if (vm.count("plugin"))
    for (const std::string& file : vm["plugin"].as<std::vector<std::string>>()) {
      if (file.empty()) throw CliError("--plugin needs a file (a kincal plug-in)");
      files.push_back(file);
    }
  for (const std::string& file : files) load_plugin(file);
}

}  // namespace kincal::cli
