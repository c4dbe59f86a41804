#pragma once
// Units of parameters, actuators and readings, as an open set. kincal computes each quantity
// in one base unit: lengths in mm, angles in rad, image coordinates in px, and whatever a
// plug-in registers (UnitRegistry::add_base). Every parameter, actuator and reading says
// which base unit it is in; other units of the same quantity (m, deg, or a plug-in's) are
// converted at the edges: measurement-file column suffixes (leg1_m, joint2_deg) and values
// per unit in options ("0.05mm,1e-4rad", "2e-5m", "0.5px"). Whatever is reported or drawn per
// quantity (simulated errors, ranges, noise) is given per unit (UnitValues).

#include <map>
#include <string>
#include <vector>

namespace kincal {

inline constexpr const char* kMillimetre = "mm";
inline constexpr const char* kRadian = "rad";
inline constexpr const char* kPixel = "px";

/// A unit: the base unit it converts to (itself for a base unit) and how.
struct Unit {
  std::string name;      ///< "deg"
  std::string base;      ///< "rad"
  double factor = 1;     ///< a value in `name` times `factor` is the value in `base`
  std::string quantity;  ///< what it measures, for messages: "an angle", "a length"
};

/// The units kincal knows. Built in: mm (lengths; m converts to it), rad (angles; deg), px
/// (image coordinates), one (dimensionless numbers: a lens's distortion coefficients),
/// rad/Nm, mm/N and rad/m (joint compliances, models/joint_compliance.hpp), kg (masses; g
/// converts to it). A plug-in adds its own when it is loaded. Thread-safe.
class UnitRegistry {
 public:
  static UnitRegistry& global();
  /// A unit quantities are computed in. Throws std::invalid_argument for a name already
  /// known, or one that is not a unit name (letters only, at most 16).
  void add_base(const std::string& name, const std::string& quantity);
  /// A unit converted to the known base unit `base` by `factor` (finite, > 0).
  void add_alias(const std::string& name, const std::string& base, double factor);
  /// The unit `name`, or nothing.
  bool find(const std::string& name, Unit* unit) const;
  /// Every unit's name, in the order they were added.
  std::vector<std::string> names() const;
  /// The units that convert to `base`, `base` first.
  std::vector<std::string> units_of(const std::string& base) const;

 private:
  UnitRegistry();
  std::vector<Unit> units_;
};

/// True for a base unit of the registry ("mm", "rad", "px", a plug-in's).
bool is_known_unit(const std::string& unit);

/// The angle wrapped to (-pi, pi].
double wrap_angle(double radians);

/// A value per base unit, e.g. parameter errors of 5 mm and 0.01 rad, or noise of 0.3 px.
class UnitValues {
 public:
  UnitValues() = default;
  UnitValues(double mm, double rad) : values_{{kMillimetre, mm}, {kRadian, rad}} {}

  /// "5mm,0.01rad", "0.5deg", "2e-5m", "0.3px", "5" (a bare number is in mm: lengths were
  /// the only unit before angles came, and every command line written then means mm). Each
  /// value is converted to its base unit (deg to rad, m to mm). Throws std::invalid_argument
  /// naming the bad part: an unknown unit, a unit given twice.
  static UnitValues parse(const std::string& text);

  bool has(const std::string& unit) const { return values_.count(unit) > 0; }
  /// The value for `unit`, or `fallback` when none was given.
  double get(const std::string& unit, double fallback = 0) const;
  void set(const std::string& unit, double value) { values_[unit] = value; }
  bool empty() const { return values_.empty(); }
  /// Whether some value is > 0.
  bool any_positive() const;
  /// Values given here replace those of `defaults`; the others are kept.
  UnitValues over(const UnitValues& defaults) const;
  /// Every value times `factor`.
  UnitValues scaled(double factor) const;
  const std::map<std::string, double>& values() const { return values_; }
  /// "5 mm, 0.01 rad".
  std::string to_string() const;

 private:
  std::map<std::string, double> values_;
};

}  // namespace kincal
