#pragma once
// Named scalar parameters of a measurement model: nominal values, units and the
// free/fixed mask that decides what a calibration estimates.

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "kincal/framework/base/types.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal {

/// The prior stds model files and --prior-std accept: beyond them the prior's precision
/// 1 / std^2 overflows (a std of 1e-320, subnormal, gives infinity) or underflows to 0.
inline constexpr double kMinPriorStd = 1e-150, kMaxPriorStd = 1e150;

struct Parameter {
  std::string name;    ///< e.g. "leg4.base.x", "gauge.offset"
  double nominal = 0;  ///< value in `unit`
  std::string unit;    ///< "mm" or "rad" (framework/kinematics/units.hpp)
  bool free = false;   ///< estimated by a calibration when true
  /// Half-width (in `unit`) of the uniform error a simulation adds to this parameter when it
  /// is free; NaN = the simulation's value for the unit. Set per parameter in model files.
  double error_half_width = std::numeric_limits<double>::quiet_NaN();
  /// Standard deviation (in `unit`) of a Gaussian prior on this parameter around `nominal`
  /// (e.g. its manufacturing tolerance); 0 = no prior. Set per parameter in model files.
  /// Readers accept kMinPriorStd to kMaxPriorStd.
  double prior_std = 0;
  bool has_prior() const { return prior_std > 0; }
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
  /// Calls `edit` on every parameter matching `pattern`; throws std::invalid_argument when the
  /// pattern matches nothing. Returns the count.
  int for_each_matching(const std::string& pattern, const std::function<void(Parameter&)>& edit);

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
