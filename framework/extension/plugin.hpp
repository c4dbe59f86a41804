#pragma once
// Plug-ins: shared libraries that add mechanism types, sensor types, presets and solver
// backends to a kincal program without rebuilding it (docs/extending.md, "Plug-ins").
//
// A plug-in is one registration function and one line in one of its source files:
//
//   void register_my_types(kincal::ModelRegistry& models, kincal::SolverRegistry& solvers);
//   KINCAL_PLUGIN(register_my_types)
//
// built with kincal_add_plugin(TARGET SOURCES...) from the installed CMake package. The
// line defines the one symbol the loader looks for, an extern "C" function that returns a
// plain C struct: the kincal version and ABI tag the plug-in was compiled against, and the
// registration function. The loader compares both strings before it calls any C++ code of
// the plug-in, so that a plug-in built against another kincal or with another compiler is
// refused with a message instead of crashing.

#include <stdexcept>
#include <string>
#include <vector>

#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/version.hpp"

// What must match between a plug-in and the program that loads it, besides the kincal
// version: the compiler family and major version, the C++ standard library and its string
// ABI, and Eigen's version and alignment (they decide the layout of every type in the
// interfaces). Computed by the preprocessor, on each side with its own compiler.
#define KINCAL_PLUGIN_STR2(x) #x
#define KINCAL_PLUGIN_STR(x) KINCAL_PLUGIN_STR2(x)
#if defined(__clang__)
#define KINCAL_PLUGIN_COMPILER "clang-" KINCAL_PLUGIN_STR(__clang_major__)
#elif defined(__GNUC__)
#define KINCAL_PLUGIN_COMPILER "gcc-" KINCAL_PLUGIN_STR(__GNUC__)
#else
#define KINCAL_PLUGIN_COMPILER "unknown-compiler"
#endif
#if defined(_GLIBCXX_USE_CXX11_ABI)
#define KINCAL_PLUGIN_STDLIB "libstdc++-cxx11abi" KINCAL_PLUGIN_STR(_GLIBCXX_USE_CXX11_ABI)
#elif defined(_LIBCPP_VERSION)
#define KINCAL_PLUGIN_STDLIB "libc++-abi" KINCAL_PLUGIN_STR(_LIBCPP_ABI_VERSION)
#else
#define KINCAL_PLUGIN_STDLIB "unknown-stdlib"
#endif
#define KINCAL_PLUGIN_ABI_TAG                                                                      \
  KINCAL_PLUGIN_COMPILER                                                                           \
  " " KINCAL_PLUGIN_STDLIB " eigen-" KINCAL_PLUGIN_STR(EIGEN_WORLD_VERSION) "." KINCAL_PLUGIN_STR( \
      EIGEN_MAJOR_VERSION) " align-" KINCAL_PLUGIN_STR(EIGEN_MAX_STATIC_ALIGN_BYTES)

extern "C" {

/// Changes only if the fields below change; checked first, so that the rest is read only
/// when its layout is known.
#define KINCAL_PLUGIN_INFO_LAYOUT 1
#define KINCAL_PLUGIN_MAGIC 0x6b63706cu /* "kcpl" */

/// What kincal_plugin_entry() returns. Plain C, readable by any kincal.
struct kincal_plugin_info {
  unsigned magic;              ///< KINCAL_PLUGIN_MAGIC
  unsigned layout;             ///< KINCAL_PLUGIN_INFO_LAYOUT
  const char* kincal_version;  ///< KINCAL_VERSION_STRING the plug-in was compiled against
  const char* abi_tag;         ///< KINCAL_PLUGIN_ABI_TAG on the plug-in's side
  void (*register_types)(kincal::ModelRegistry&, kincal::SolverRegistry&);
};
}

/// The name of the entry symbol, for dlsym.
#define KINCAL_PLUGIN_ENTRY_SYMBOL "kincal_plugin_entry"

/// In one source file of the plug-in: `fn` registers its types (see the top of this file).
#define KINCAL_PLUGIN(fn)                                                                       \
  extern "C" __attribute__((visibility("default"))) const kincal_plugin_info*                   \
  kincal_plugin_entry() {                                                                       \
    static const kincal_plugin_info info = {KINCAL_PLUGIN_MAGIC, KINCAL_PLUGIN_INFO_LAYOUT,     \
                                            KINCAL_VERSION_STRING, KINCAL_PLUGIN_ABI_TAG, &fn}; \
    return &info;                                                                               \
  }

namespace kincal {

/// A plug-in that cannot be loaded: not found, not a plug-in, built against another kincal
/// or compiler, a name that clashes, or a registration that threw. One sentence naming the
/// file.
class PluginError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What this build of kincal requires of a plug-in: "<version> <abi tag>".
std::string plugin_abi_description();

/// Loads the plug-in `path` (a file name; no search) and adds what it registers to
/// `models` and `solvers`, by default the global registries. Everything or nothing: a
/// plug-in whose names clash with registered ones (built in or from another plug-in) adds
/// nothing, and the error names both. Loading the same file into the same registries again
/// does nothing. (Model files are read through ModelRegistry::global(): load into the
/// global registries to read and write the plug-in's types from files.) The
/// library stays loaded for the life of the process (registered types point into it).
/// Throws PluginError.
void load_plugin(const std::string& path, ModelRegistry& models = ModelRegistry::global(),
                 SolverRegistry& solvers = SolverRegistry::global());

/// The plug-ins named by the environment variable KINCAL_PLUGIN_PATH: a colon-separated list
/// of plug-in files and folders (a folder: every *.so in it, in name order). Unset or empty:
/// none. Returns the files, in the order to load them; throws PluginError for an entry that
/// does not exist.
std::vector<std::string> plugins_from_environment();

/// Every plug-in loaded so far in this process, in load order (absolute paths).
std::vector<std::string> loaded_plugins();

/// The plug-in file (absolute path) that registered `name` as a `kind` ("mechanism type",
/// "sensor type", "constraint type", "preset" or "solver"; a solver family by its name before ':'),
/// or "" for what is built in. Lets `kincal list` say where a type came from.
std::string plugin_providing(const std::string& kind, const std::string& name);

}  // namespace kincal
