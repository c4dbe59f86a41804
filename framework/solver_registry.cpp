#include "framework/solver_registry.hpp"

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

void SolverRegistry::add(const std::string& name, const std::string& description, Factory factory,
                         std::vector<std::string> featured_variants, bool is_family) {
  for (const auto& info : infos_)
    if (info.name == name || info.name == name + ":<ALGORITHM>")
      throw std::logic_error("solver '" + name + "' registered twice");
  SolverInfo info;
  info.name = is_family ? name + ":<ALGORITHM>" : name;
  info.description = description;
  info.variants = is_family ? std::move(featured_variants) : std::vector<std::string>{name};
  if (is_family)
    for (auto& v : info.variants) v = name + ":" + v;
  infos_.push_back(std::move(info));
  entries_.push_back({is_family, std::move(factory)});
}

bool SolverRegistry::contains(const std::string& name) const {
  try {
    create(name);
    return true;
  } catch (const InvalidSolverOptions&) {
    return false;
  }
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
  std::string known;
  for (const auto& info : infos_) known += (known.empty() ? "" : ", ") + info.name;
  throw InvalidSolverOptions("unknown solver '" + name + "' (available: " + known + ")");
}

std::vector<std::string> SolverRegistry::featured_names() const {
  std::vector<std::string> names;
  for (const auto& info : infos_)
    for (const auto& v : info.variants) names.push_back(v);
  return names;
}

}  // namespace kincal
