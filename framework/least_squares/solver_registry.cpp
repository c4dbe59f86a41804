#include "kincal/framework/least_squares/solver_registry.hpp"

#include <stdexcept>

namespace kincal {

SolverRegistry& SolverRegistry::global() {
  static SolverRegistry registry = [] {
    SolverRegistry r;
    register_builtin_solvers(r);
    return r;
  }();
  return registry;
}

void SolverRegistry::require_new_name(const std::string& name) const {
  if (name.empty() || name.find(':') != std::string::npos)
    throw std::logic_error("solver name '" + name + "' must be non-empty, without a colon");
  for (const auto& info : infos_)
    if (info.name == name || info.name == name + ":<ALGORITHM>")
      throw std::logic_error("solver '" + name + "' registered twice");
  for (const auto& missing : unavailable_)
    if (missing.name == name) throw std::logic_error("solver '" + name + "' registered twice");
}

void SolverRegistry::add_entry(SolverInfo info, bool is_family, Factory factory) {
  infos_.push_back(std::move(info));
  entries_.push_back({is_family, std::move(factory)});
}

void SolverRegistry::add(const std::string& name, const std::string& description, SolverKind kind,
                         Factory factory) {
  require_new_name(name);
  add_entry({name, description, kind, {name}}, false, std::move(factory));
}

void SolverRegistry::add_family(const std::string& family, const std::string& description,
                                SolverKind kind, Factory factory,
                                std::vector<std::string> featured_variants) {
  require_new_name(family);
  for (auto& v : featured_variants) v = family + ":" + v;
  add_entry({family + ":<ALGORITHM>", description, kind, std::move(featured_variants)}, true,
            std::move(factory));
}

void SolverRegistry::add_unavailable(const std::string& name, SolverKind kind,
                                     const std::string& reason) {
  require_new_name(name);
  unavailable_.push_back({name, kind, reason});
}

void SolverRegistry::add_all(const SolverRegistry& other) {
  for (std::size_t i = 0; i < other.infos_.size(); ++i) {
    const SolverInfo& info = other.infos_[i];
    require_new_name(info.name.substr(0, info.name.find(':')));
    add_entry(info, other.entries_[i].is_family, other.entries_[i].factory);
  }
  for (const auto& missing : other.unavailable_)
    add_unavailable(missing.name, missing.kind, missing.reason);
}

bool SolverRegistry::contains_name(const std::string& name) const {
  for (const auto& info : infos_)
    if (info.name == name || info.name == name + ":<ALGORITHM>") return true;
  for (const auto& missing : unavailable_)
    if (missing.name == name) return true;
  return false;
}

bool SolverRegistry::contains(const std::string& name) const {
  try {
    create(name);
    return true;
  } catch (const InvalidSolverOptions&) {
    return false;
  }
}

std::string SolverRegistry::available_names() const {
  std::string known;
  for (const auto& info : infos_) known += (known.empty() ? "" : ", ") + info.name;
  return known;
}

std::unique_ptr<Solver> SolverRegistry::create(const std::string& name) const {
  const auto colon = name.find(':');
  const std::string family = name.substr(0, colon);
  for (std::size_t i = 0; i < infos_.size(); ++i) {
    if (entries_[i].is_family) {
      if (colon != std::string::npos && infos_[i].name == family + ":<ALGORITHM>")
        return entries_[i].factory(name.substr(colon + 1));
    } else if (infos_[i].name == name) {
      return entries_[i].factory("");
    }
  }
  for (const auto& missing : unavailable_)
    if (missing.name == family)
      throw InvalidSolverOptions("solver '" + name + "' is not in this build: " + missing.reason +
                                 " (available: " + available_names() + ")");
  throw InvalidSolverOptions("unknown solver '" + name + "' (available: " + available_names() +
                             ")");
}

std::vector<std::string> SolverRegistry::featured_names() const {
  std::vector<std::string> names;
  for (const auto& info : infos_)
    for (const auto& v : info.variants) names.push_back(v);
  return names;
}

}  // namespace kincal
