#pragma once
// Backends by name. Registration is explicit (register_builtin_solvers() in solvers/):
// static self-registration silently vanishes when linking a static library.
//
// A name is either exact ("gn") or a family with a variant after a colon
// ("nlopt:LD_LBFGS"): the family's factory receives the variant and rejects unknown ones.
// Backends that this build leaves out (their KINCAL_WITH_<NAME> option was OFF) are
// registered as unavailable, so that asking for one says why it is missing and tests can
// skip them by name instead of silently losing them.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

/// How a backend treats the problem; the conformance suite holds each kind to its own
/// standard (docs/solvers.md, "The conformance suite").
enum class SolverKind {
  /// Exploits the least-squares structure (a Gauss-Newton model J^T J), so it must reach the
  /// least-squares minimum itself: the truth to 1e-6 mm on noise-free data, and lm's minimum
  /// to 1e-6 mm on noisy data.
  kLeastSquares,
  /// A general-purpose minimiser of 1/2 |r|^2 (NLopt): looser, documented bounds.
  kGeneralMinimizer,
};

struct SolverInfo {
  std::string name;         ///< "gn", or a family as "nlopt:<ALGORITHM>"
  std::string description;  ///< one line
  SolverKind kind = SolverKind::kLeastSquares;
  /// Concrete names worth testing and benchmarking ("nlopt:LD_LBFGS", ...); {name} for
  /// exact entries.
  std::vector<std::string> variants;
};

/// A backend kincal has but this build leaves out.
struct UnavailableSolver {
  std::string name;  ///< exact name or family, without a colon ("ceres", "nlopt")
  SolverKind kind = SolverKind::kLeastSquares;
  std::string reason;  ///< how to get it, e.g. "configure with -DKINCAL_WITH_CERES=ON"
};

class SolverRegistry {
 public:
  using Factory = std::function<std::unique_ptr<Solver>(const std::string& variant)>;

  /// The process-wide registry with the built-in backends registered.
  static SolverRegistry& global();

  /// An exact name (no colon). Throws std::logic_error when the name is already taken.
  void add(const std::string& name, const std::string& description, SolverKind kind,
           Factory factory);
  /// A family (no colon): names are "family:VARIANT", and the factory validates VARIANT.
  void add_family(const std::string& family, const std::string& description, SolverKind kind,
                  Factory factory, std::vector<std::string> featured_variants);
  /// A backend left out of this build: create() on its name (or "name:VARIANT") throws
  /// InvalidSolverOptions with `reason`.
  void add_unavailable(const std::string& name, SolverKind kind, const std::string& reason);

  /// Adds every backend of `other` (a plug-in's), with the same checks as add().
  void add_all(const SolverRegistry& other);

  bool contains(const std::string& name) const;
  /// Whether `name` (an exact name or a family, without a colon) is taken, available or not.
  bool contains_name(const std::string& name) const;
  /// Throws InvalidSolverOptions listing the registered names when `name` is unknown, or
  /// giving the reason when it belongs to an unavailable backend.
  std::unique_ptr<Solver> create(const std::string& name) const;
  const std::vector<SolverInfo>& list() const { return infos_; }
  /// Backends left out of this build, in registration order.
  const std::vector<UnavailableSolver>& unavailable() const { return unavailable_; }
  /// Every concrete, featured solver name, in registration order.
  std::vector<std::string> featured_names() const;

 private:
  struct Entry {
    bool is_family;
    Factory factory;
  };
  void add_entry(SolverInfo info, bool is_family, Factory factory);
  void require_new_name(const std::string& name) const;
  std::string available_names() const;

  std::vector<SolverInfo> infos_;
  std::vector<Entry> entries_;
  std::vector<UnavailableSolver> unavailable_;
};

/// Defined in solvers/builtin_solvers.cpp: registers every backend built into this library
/// and, as unavailable, each optional one that is not.
void register_builtin_solvers(SolverRegistry& registry);

}  // namespace kincal
