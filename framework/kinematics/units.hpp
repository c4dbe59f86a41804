#pragma once
// Units of parameters, actuators and readings. kincal computes in millimetres and radians;
// every parameter, actuator and reading says which of the two it is in, and whatever is
// reported or drawn per quantity (simulated errors, ranges, noise) is given per unit.

#include <map>
#include <string>

namespace kincal {

inline constexpr const char* kMillimetre = "mm";
inline constexpr const char* kRadian = "rad";

/// True for "mm" and "rad".
bool is_known_unit(const std::string& unit);

/// The angle wrapped to (-pi, pi].
double wrap_angle(double radians);

/// A value per unit, e.g. parameter errors of 5 mm and 0.01 rad.
class UnitValues {
 public:
  UnitValues() = default;
  UnitValues(double mm, double rad) : values_{{kMillimetre, mm}, {kRadian, rad}} {}

  /// "5mm,0.01rad", "0.5deg", "5" (a bare number is in mm: lengths were the only unit before
  /// angles came, and every command line written then means mm). "deg" is converted to rad.
  /// Throws std::invalid_argument naming the bad part.
  static UnitValues parse(const std::string& text);

  bool has(const std::string& unit) const { return values_.count(unit) > 0; }
  /// The value for `unit`, or `fallback` when none was given.
  double get(const std::string& unit, double fallback = 0) const;
  void set(const std::string& unit, double value) { values_[unit] = value; }
  /// Values given here replace those of `defaults`; the others are kept.
  UnitValues over(const UnitValues& defaults) const;
  const std::map<std::string, double>& values() const { return values_; }
  /// "5 mm, 0.01 rad".
  std::string to_string() const;

 private:
  std::map<std::string, double> values_;
};

}  // namespace kincal
