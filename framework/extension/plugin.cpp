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
#include "kincal/framework/kinematics/model_names.hpp"
#include "kincal/framework/kinematics/names.hpp"

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

// ---- the names a plug-in registers -----------------------------------------------------

// The first name or description `models` and `solvers` (a plug-in's, just registered) hold
// that the name policy refuses (framework/kinematics/names.hpp), as "<kind> '<name>' <problem>",
// or "". Names become columns, CSV cells and report keys; descriptions are printed by
// kincal list.
std::string registered_name_problem(const ModelRegistry& models, const SolverRegistry& solvers) {
  std::string problem;
  const auto name = [&problem](const std::string& kind, const std::string& text) {
    if (problem.empty()) {
      const std::string why = name_problem(text);
      if (!why.empty()) problem = kind + " '" + message_excerpt(text) + "' " + why;
    }
  };
  const auto text = [&problem](const std::string& kind, const std::string& owner,
                               const std::string& description) {
    if (problem.empty()) {
      const std::string why = text_problem(description);
      if (!why.empty())
        problem = "the description of " + kind + " '" + message_excerpt(owner) + "' " + why;
    }
  };
  for (const auto& t : models.mechanisms()) {
    name("mechanism type", t.type);
    text("mechanism type", t.type, t.description);
  }
  for (const auto& t : models.sensors()) {
    name("sensor type", t.type);
    text("sensor type", t.type, t.description);
  }
  for (const auto& t : models.constraints()) {
    name("constraint type", t.type);
    text("constraint type", t.type, t.description);
  }
  for (const auto& p : models.presets()) {
    name("preset", p.name);
    text("preset", p.name, p.description);
  }
  for (const auto& f : models.export_formats()) {
    name("export format", f.format);
    name("export format's mechanism type", f.mechanism_type);
    text("export format", f.format, f.description);
  }
  for (const auto& info : solvers.list()) {
    const std::string family = info.name.substr(0, info.name.find(':'));
    name("solver", family);
    text("solver", family, info.description);
    for (const auto& variant : info.variants)
      if (variant.find(':') != std::string::npos)
        name("solver variant", variant.substr(variant.find(':') + 1));
  }
  for (const auto& missing : solvers.unavailable()) {
    name("solver", missing.name);
    text("unavailable solver", missing.name, missing.reason);
  }
  return problem;
}

// ---- calls into a plug-in --------------------------------------------------------------

// `f`, a function of the plug-in, such that what it throws that is not a std::exception
// (`throw 42;`) becomes a PluginError naming the plug-in and `what` it was asked to do,
// instead of ending the program in std::terminate. A std::exception passes unchanged:
// readers report bad input with theirs.
template <class F>
auto guarded(const std::string& where, const std::string& what, F f) {
  return [where, what, f = std::move(f)](auto&&... args) {
    try {
      return f(std::forward<decltype(args)>(args)...);
    } catch (const std::exception&) {
      throw;
    } catch (...) {
      throw PluginError(where + ": " + what +
                        " threw an exception that is not a std::exception (a plug-in must throw "
                        "std::exception or a class derived from it)");
    }
  };
}

// `result` of the plug-in's `what`, refused when null: kincal would dereference it.
template <class Pointer>
Pointer non_null(Pointer result, const std::string& where, const std::string& what) {
  if (!result) throw PluginError(where + ": " + what + " returned null");
  return result;
}

// Every function of the plug-in's `scratch` entries, guarded (what a reader or factory makes
// checked too), added to `models`.
void add_guarded(const ModelRegistry& scratch, ModelRegistry& models, const std::string& where) {
  for (MechanismType t : scratch.mechanisms()) {
    const std::string what = "mechanism type '" + t.type + "'";
    t.read = [read = guarded(where, what + "'s reader", t.read), where, what](const Json& object,
                                                                              const JsonPath& at) {
      return non_null(read(object, at), where, what + "'s reader");
    };
    t.write = guarded(where, what + "'s writer", t.write);
    models.add_mechanism(t);
  }
  for (SensorType t : scratch.sensors()) {
    const std::string what = "sensor type '" + t.type + "'";
    t.read = [read = guarded(where, what + "'s reader", t.read), where, what](const Json& object,
                                                                              const JsonPath& at) {
      return non_null(read(object, at), where, what + "'s reader");
    };
    t.write = guarded(where, what + "'s writer", t.write);
    models.add_sensor(t);
  }
  for (ConstraintType t : scratch.constraints()) {
    const std::string what = "constraint type '" + t.type + "'";
    t.read = [read = guarded(where, what + "'s reader", t.read), where, what](
                 const Json& object, const JsonPath& at, const MeasurementModel& model) {
      return non_null(read(object, at, model), where, what + "'s reader");
    };
    t.write = guarded(where, what + "'s writer", t.write);
    models.add_constraint(t);
  }
  for (ModelPreset p : scratch.presets()) {
    // A preset's model reaches files and the terminal without a model file's checks: its
    // names are held to the same policy here.
    const std::string what = "preset '" + p.name + "'";
    p.make = [make = guarded(where, what, p.make), where, what]() {
      std::shared_ptr<MeasurementModel> model = non_null(make(), where, what);
      const std::string problem = model_name_problem(*model);
      if (!problem.empty())
        throw PluginError(where + ": " + what + " makes a model whose " + problem);
      return model;
    };
    models.add_preset(p);
  }
  for (ExportFormat f : scratch.export_formats()) {
    f.write = guarded(where, "export format '" + f.format + "'", f.write);
    models.add_export_format(f);
  }
}

// The plug-in's backends, added to `solvers` through factories that call the plug-in's
// (kept alive by them) guarded: a throw that is not a std::exception or a null solver is a
// PluginError naming the plug-in and the solver.
void add_guarded(std::shared_ptr<const SolverRegistry> scratch, SolverRegistry& solvers,
                 const std::string& where) {
  for (const SolverInfo& info : scratch->list()) {
    const auto colon = info.name.find(':');
    const bool family = colon != std::string::npos;
    const std::string name = info.name.substr(0, colon);
    SolverRegistry::Factory factory = [scratch, name, family, where](const std::string& variant) {
      const std::string solver = family ? name + ":" + variant : name;
      const std::string what = "solver '" + message_excerpt(solver) + "'";
      return non_null(guarded(where, what, [&] { return scratch->create(solver); })(), where,
                      what + "'s factory");
    };
    if (!family) {
      solvers.add(name, info.description, info.kind, std::move(factory));
      continue;
    }
    std::vector<std::string> variants;
    for (const std::string& v : info.variants) variants.push_back(v.substr(v.find(':') + 1));
    solvers.add_family(name, info.description, info.kind, std::move(factory), variants);
  }
  for (const UnavailableSolver& missing : scratch->unavailable())
    solvers.add_unavailable(missing.name, missing.kind, missing.reason);
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
  const kincal_plugin_info* info = nullptr;
  try {
    info = entry();
  } catch (...) {
    throw PluginError(where + ": its " KINCAL_PLUGIN_ENTRY_SYMBOL " threw an exception");
  }
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
  // Shared: the guarded factories added to `solvers` call the plug-in's through it.
  const auto scratch_solver_registry = std::make_shared<SolverRegistry>();
  SolverRegistry& scratch_solvers = *scratch_solver_registry;
  try {
    info->register_types(scratch_models, scratch_solvers);
  } catch (const std::exception& e) {
    throw PluginError(where + ": its registration failed: " + message_excerpt(e.what()));
  } catch (...) {
    throw PluginError(where +
                      ": its registration threw an exception that is not a std::exception (a "
                      "plug-in must throw std::exception or a class derived from it)");
  }
  const std::string bad_name = registered_name_problem(scratch_models, scratch_solvers);
  if (!bad_name.empty())
    throw PluginError(where + " registers a name kincal does not accept: " + bad_name +
                      " (docs/reliability.md, \"Names\")");
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
  add_guarded(scratch_models, models, where);
  add_guarded(scratch_solver_registry, solvers, where);

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
