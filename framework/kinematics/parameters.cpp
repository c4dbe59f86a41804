#include "kincal/framework/kinematics/parameters.hpp"

#include <stdexcept>
#include <unordered_set>

namespace kincal {

bool glob_match(const std::string& pattern, const std::string& name) {
  // Iterative matcher with single-star backtracking: linear for the patterns people type.
  std::size_t p = 0, n = 0, star = std::string::npos, mark = 0;
  while (n < name.size()) {
    if (p < pattern.size() && (pattern[p] == '?' || pattern[p] == name[n])) {
      ++p;
      ++n;
    } else if (p < pattern.size() && pattern[p] == '*') {
      star = p++;
      mark = n;
    } else if (star != std::string::npos) {
      p = star + 1;
      n = ++mark;
    } else {
      return false;
    }
  }
  while (p < pattern.size() && pattern[p] == '*') ++p;
  return p == pattern.size();
}

ParameterSet::ParameterSet(std::vector<Parameter> parameters) { append(parameters); }

void ParameterSet::append(const std::vector<Parameter>& other) {
  std::unordered_set<std::string> seen;
  for (const auto& p : parameters_) seen.insert(p.name);
  for (const auto& p : other) {
    if (!seen.insert(p.name).second)
      throw std::invalid_argument("duplicate parameter name '" + p.name + "'");
    parameters_.push_back(p);
  }
}

int ParameterSet::find(const std::string& name) const {
  for (int i = 0; i < size(); ++i)
    if (parameters_[i].name == name) return i;
  return -1;
}

int ParameterSet::index_of(const std::string& name) const {
  const int i = find(name);
  if (i < 0) throw std::invalid_argument("unknown parameter '" + name + "'");
  return i;
}

int ParameterSet::set_free(const std::string& pattern, bool free) {
  return for_each_matching(pattern, [free](Parameter& p) { p.free = free; });
}

int ParameterSet::for_each_matching(const std::string& pattern,
                                    const std::function<void(Parameter&)>& edit) {
  int count = 0;
  for (auto& p : parameters_) {
    if (glob_match(pattern, p.name)) {
      edit(p);
      ++count;
    }
  }
  if (count == 0)
    throw std::invalid_argument("parameter pattern '" + pattern + "' matches no parameter");
  return count;
}

VectorXd ParameterSet::nominal_values() const {
  VectorXd v(size());
  for (int i = 0; i < size(); ++i) v[i] = parameters_[i].nominal;
  return v;
}

std::vector<int> ParameterSet::free_indices() const {
  std::vector<int> idx;
  for (int i = 0; i < size(); ++i)
    if (parameters_[i].free) idx.push_back(i);
  return idx;
}

std::vector<std::string> ParameterSet::names() const {
  std::vector<std::string> out;
  out.reserve(parameters_.size());
  for (const auto& p : parameters_) out.push_back(p.name);
  return out;
}

int ParameterSet::num_free() const { return static_cast<int>(free_indices().size()); }

}  // namespace kincal
