#pragma once
// Backends by name. Registration is explicit (register_builtin_solvers() in solvers/):
// static self-registration silently vanishes when linking a static library.
//
// A name is either exact ("gn") or a family with a variant after a colon
// ("nlopt:LD_LBFGS"): the family's factory receives the variant and rejects unknown ones.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "framework/solver.hpp"

namespace kincal {

struct SolverInfo {
  std::string name;         ///< "gn", or a family as "nlopt:<ALGORITHM>"
  std::string description;  ///< one line
  /// Concrete names worth testing and benchmarking ("nlopt:LD_LBFGS", ...); {name} for
  /// exact entries.
  std::vector<std::string> variants;
};

class SolverRegistry {
 public:
  using Factory = std::function<std::unique_ptr<Solver>(const std::string& variant)>;

  /// The process-wide registry with the built-in backends registered.
  static SolverRegistry& global();

  /// Exact name (no colon) or family (`family` must not contain a colon; names are
  /// "family:VARIANT"). Throws std::logic_error on duplicates.
  void add(const std::string& name, const std::string& description, Factory factory,
           std::vector<std::string> featured_variants = {}, bool is_family = false);

  bool contains(const std::string& name) const;
  /// Throws InvalidSolverOptions listing the registered names when `name` is unknown.
  std::unique_ptr<Solver> create(const std::string& name) const;
  const std::vector<SolverInfo>& list() const { return infos_; }
  /// Every concrete, featured solver name, in registration order.
  std::vector<std::string> featured_names() const;

 private:
  struct Entry {
    bool is_family;
    Factory factory;
  };
  std::vector<SolverInfo> infos_;
  std::vector<Entry> entries_;
};

/// Defined in solvers/builtin_solvers.cpp: registers every backend built into this library.
void register_builtin_solvers(SolverRegistry& registry);

}  // namespace kincal
