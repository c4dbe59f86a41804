#include "kincal/framework/extension/plugin.hpp"

#include <dirent.h>
#include <dlfcn.h>
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <set>
#include <tuple>

#include "kincal/framework/base/message_excerpt.hpp"

namespace kincal {

namespace {

struct LoadedPlugins {
  std::mutex mutex;
  std::vector<std::string> files;  // absolute, in load order
  // Which file went into which registries: loading it into the same ones again is a no-op.
  std::set<std::tuple<std::string, const ModelRegistry*, const SolverRegistry*>> loaded_into;
  std::map<std::string, std::string> owner_of_name;  // "mechanism type 'x'" -> plug-in file
};

LoadedPlugins& loaded() {
  static LoadedPlugins state;
  return state;
}

std::string absolute(const std::string& path) {
  char resolved[PATH_MAX];
  if (::realpath(path.c_str(), resolved)) return resolved;
  return path;
}

// The names `scratch` registers that `target` has already, each as "<kind> '<name>'".
std::vector<std::string> clashes(const ModelRegistry& scratch,
                                 const SolverRegistry& scratch_solvers, const ModelRegistry& target,
                                 const SolverRegistry& solvers) {
  std::vector<std::string> out;
  auto check = [&](const auto& mine, const auto& theirs, auto name_of, const char* kind) {
    for (const auto& a : mine)
      for (const auto& b : theirs)
        if (name_of(a) == name_of(b)) out.push_back(std::string(kind) + " '" + name_of(a) + "'");
  };
  check(
      scratch.mechanisms(), target.mechanisms(), [](const auto& t) { return t.type; },
      "mechanism type");
  check(
      scratch.sensors(), target.sensors(), [](const auto& t) { return t.type; }, "sensor type");
  check(
      scratch.presets(), target.presets(), [](const auto& p) { return p.name; }, "preset");
  check(
      scratch.constraints(), target.constraints(), [](const auto& t) { return t.type; },
      "constraint type");
  check(
      scratch.export_formats(), target.export_formats(),
      [](const auto& f) { return f.mechanism_type + "/" + f.format; }, "export format");
  for (const auto& info : scratch_solvers.list()) {
    const std::string name = info.name.substr(0, info.name.find(':'));
    if (solvers.contains_name(name)) out.push_back("solver '" + name + "'");
  }
  return out;
}

template <class Entries, class NameOf>
void remember_owner(std::map<std::string, std::string>& owners, const Entries& entries,
                    NameOf name_of, const char* kind, const std::string& file) {
  for (const auto& e : entries) owners[std::string(kind) + " '" + name_of(e) + "'"] = file;
}

}  // namespace

std::string plugin_abi_description() {
  return std::string("kincal ") + KINCAL_VERSION_STRING + ", " + KINCAL_PLUGIN_ABI_TAG;
}

void load_plugin(const std::string& path, ModelRegistry& models, SolverRegistry& solvers) {
  // The whole path (escaped, not cut): a clash must name the file the user gave.
  const std::string where = "plug-in '" + printable(path) + "'";
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw PluginError(where + ": " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw PluginError(where + ": not a file");
  const std::string file = absolute(path);
  LoadedPlugins& state = loaded();
  std::lock_guard<std::mutex> lock(state.mutex);
  if (state.loaded_into.count({file, &models, &solvers})) return;

  // dlopen needs a slash to take the name as a path rather than search the library path.
  const std::string open_name = file.find('/') == std::string::npos ? "./" + file : file;
  // Never closed: the registered types' code and tables live in it.
  void* handle = ::dlopen(open_name.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = ::dlerror();
    throw PluginError(where + ": cannot be loaded (" +
                      message_excerpt(why ? why : "dlopen failed") + ")");
  }
  using Entry = const kincal_plugin_info* (*)();
  auto entry = reinterpret_cast<Entry>(::dlsym(handle, KINCAL_PLUGIN_ENTRY_SYMBOL));
  if (!entry)
    throw PluginError(where + ": not a kincal plug-in (it defines no " KINCAL_PLUGIN_ENTRY_SYMBOL
                              "; one source file needs KINCAL_PLUGIN(your_register_function))");
  const kincal_plugin_info* info = entry();
  if (!info || info->magic != KINCAL_PLUGIN_MAGIC)
    throw PluginError(where + ": its " KINCAL_PLUGIN_ENTRY_SYMBOL " is not kincal's");
  if (info->layout != KINCAL_PLUGIN_INFO_LAYOUT)
    throw PluginError(where + ": built for another kincal plug-in interface (layout " +
                      std::to_string(info->layout) + ", this kincal reads layout " +
                      std::to_string(KINCAL_PLUGIN_INFO_LAYOUT) +
                      "); rebuild it against this kincal");
  const std::string version = info->kincal_version ? info->kincal_version : "?";
  const std::string abi = info->abi_tag ? info->abi_tag : "?";
  if (version != KINCAL_VERSION_STRING || abi != KINCAL_PLUGIN_ABI_TAG)
    throw PluginError(where + ": built against kincal " + message_excerpt(version) + ", " +
                      message_excerpt(abi) + "; this program is " + plugin_abi_description() +
                      ": rebuild the plug-in against this kincal with the same compiler");
  if (!info->register_types) throw PluginError(where + ": registers nothing (no function)");

  // Into empty registries first, so that a clash or a throw adds nothing.
  ModelRegistry scratch_models;
  SolverRegistry scratch_solvers;
  try {
    info->register_types(scratch_models, scratch_solvers);
  } catch (const std::exception& e) {
    throw PluginError(where + ": its registration failed: " + message_excerpt(e.what()));
  }
  const std::vector<std::string> clashing =
      clashes(scratch_models, scratch_solvers, models, solvers);
  if (!clashing.empty()) {
    std::string list;
    for (const auto& c : clashing) {
      const auto owner = state.owner_of_name.find(c);
      list += (list.empty() ? "" : "; ") + c + " (registered by " +
              (owner == state.owner_of_name.end() ? std::string("kincal or the program, built in")
                                                  : "plug-in '" + owner->second + "'") +
              ")";
    }
    throw PluginError(where + " registers names that are taken: " + list);
  }
  for (const auto& t : scratch_models.mechanisms()) models.add_mechanism(t);
  for (const auto& t : scratch_models.sensors()) models.add_sensor(t);
  for (const auto& p : scratch_models.presets()) models.add_preset(p);
  for (const auto& f : scratch_models.export_formats()) models.add_export_format(f);
  for (const auto& c : scratch_models.constraints()) models.add_constraint(c);
  solvers.add_all(scratch_solvers);

  auto& owners = state.owner_of_name;
  remember_owner(
      owners, scratch_models.mechanisms(), [](const auto& t) { return t.type; }, "mechanism type",
      file);
  remember_owner(
      owners, scratch_models.sensors(), [](const auto& t) { return t.type; }, "sensor type", file);
  remember_owner(
      owners, scratch_models.presets(), [](const auto& p) { return p.name; }, "preset", file);
  remember_owner(
      owners, scratch_models.constraints(), [](const auto& c) { return c.type; }, "constraint type",
      file);
  for (const auto& info_entry : scratch_solvers.list())
    owners["solver '" + info_entry.name.substr(0, info_entry.name.find(':')) + "'"] = file;
  state.loaded_into.insert({file, &models, &solvers});
  if (std::find(state.files.begin(), state.files.end(), file) == state.files.end())
    state.files.push_back(file);
}

std::vector<std::string> plugins_from_environment() {
  const char* value = std::getenv("KINCAL_PLUGIN_PATH");
  std::vector<std::string> files;
  if (!value) return files;
  const std::string list = value;
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t colon = std::min(list.find(':', start), list.size());
    const std::string entry = list.substr(start, colon - start);
    start = colon + 1;
    if (entry.empty()) continue;
    struct stat st {};
    if (::stat(entry.c_str(), &st) != 0)
      throw PluginError("KINCAL_PLUGIN_PATH: '" + message_excerpt(entry) +
                        "': " + std::strerror(errno));
    if (!S_ISDIR(st.st_mode)) {
      files.push_back(entry);
      continue;
    }
    std::vector<std::string> in_folder;
    if (DIR* dir = ::opendir(entry.c_str())) {
      while (const dirent* e = ::readdir(dir)) {
        const std::string name = e->d_name;
        if (name.size() > 3 && name.compare(name.size() - 3, 3, ".so") == 0)
          in_folder.push_back(entry + "/" + name);
      }
      ::closedir(dir);
    } else {
      throw PluginError("KINCAL_PLUGIN_PATH: '" + message_excerpt(entry) +
                        "': " + std::strerror(errno));
    }
    std::sort(in_folder.begin(), in_folder.end());
    files.insert(files.end(), in_folder.begin(), in_folder.end());
  }
  return files;
}

std::string plugin_providing(const std::string& kind, const std::string& name) {
  auto& state = loaded();
  std::lock_guard<std::mutex> lock(state.mutex);
  const std::string key =
      kind + " '" + (kind == "solver" ? name.substr(0, name.find(':')) : name) + "'";
  const auto it = state.owner_of_name.find(key);
  return it == state.owner_of_name.end() ? std::string() : it->second;
}

std::vector<std::string> loaded_plugins() {
  LoadedPlugins& state = loaded();
  std::lock_guard<std::mutex> lock(state.mutex);
  return state.files;
}

}  // namespace kincal
