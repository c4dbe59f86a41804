#pragma once
// --plugin FILE, which every command takes, and KINCAL_PLUGIN_PATH: which plug-ins a run
// loads, and when. A plug-in is code that runs with the user's rights, so only a real option
// token loads one: the arguments are parsed with the command's own options (which know which
// options take a value) plus --plugin, and the plug-ins are loaded after that parse, before
// the command reads a model, a preset or a solver name (which may be a plug-in's). A value of
// another option (`--data --plugin=x.so`, `--out=--plugin=x.so`) and anything after `--`
// never loads a plug-in (docs/extending.md, "Which plug-ins a run loads").

#include <boost/program_options.hpp>

namespace kincal::cli {

/// Adds --plugin FILE (repeatable) to a command's options; parse_command_line does it for
/// every command that uses it.
void add_plugin_option(boost::program_options::options_description& options);

/// Loads KINCAL_PLUGIN_PATH's plug-ins, then --plugin's in the order given, into the global
/// registries. Call it once the command line has parsed, before anything that needs the
/// registries. Throws PluginError, or CliError for an empty --plugin.
void load_plugins(const boost::program_options::variables_map& vm);

}  // namespace kincal::cli
