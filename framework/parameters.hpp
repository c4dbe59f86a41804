#pragma once
// Named scalar parameters of a measurement model: nominal values, units and the
// free/fixed mask that decides what a calibration estimates.

#include <string>
#include <vector>

#include "kincal/framework/types.hpp"

namespace kincal {

struct Parameter {
  std::string name;    ///< e.g. "leg4.base.x", "gauge.offset"
  double nominal = 0;  ///< value in `unit`
  std::string unit;    ///< "mm" for every kinematic parameter so far
  bool free = false;   ///< estimated by a calibration when true
};

/// True when `name` matches the glob `pattern` ('*' any run, '?' one character).
bool glob_match(const std::string& pattern, const std::string& name);

class ParameterSet {
 public:
  ParameterSet() = default;
  explicit ParameterSet(std::vector<Parameter> parameters);

  int size() const { return static_cast<int>(parameters_.size()); }
  const Parameter& operator[](int i) const { return parameters_[i]; }
  const std::vector<Parameter>& all() const { return parameters_; }

  /// Index of `name`, or -1.
  int find(const std::string& name) const;
  /// Index of `name`; throws std::invalid_argument naming it when unknown.
  int index_of(const std::string& name) const;

  /// Marks every parameter matching `pattern` free (or fixed). Throws std::invalid_argument
  /// when the pattern matches nothing, so a typo never passes silently. Returns the count.
  int set_free(const std::string& pattern, bool free);

  VectorXd nominal_values() const;
  std::vector<int> free_indices() const;
  std::vector<std::string> names() const;
  int num_free() const;

  /// Appends the parameters of `other`, each name prefixed by nothing (names are global).
  void append(const std::vector<Parameter>& other);

 private:
  std::vector<Parameter> parameters_;
};

}  // namespace kincal
