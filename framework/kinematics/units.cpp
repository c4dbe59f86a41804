#include "kincal/framework/kinematics/units.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <stdexcept>

#include "kincal/framework/base/angles.hpp"

namespace kincal {

namespace {

std::mutex& registry_mutex() {
  static std::mutex mutex;
  return mutex;
}

bool is_unit_name(const std::string& name) {
  if (name.empty() || name.size() > 16) return false;
  for (const char c : name)
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'))) return false;
  return true;
}

}  // namespace

UnitRegistry::UnitRegistry()
    : units_{{kMillimetre, kMillimetre, 1, "a length"},
             {"m", kMillimetre, 1000, "a length"},
             {kRadian, kRadian, 1, "an angle"},
             {"deg", kRadian, kRadiansPerDegree, "an angle"},
             {kPixel, kPixel, 1, "an image coordinate"},
             // SI's unit one, of dimensionless numbers (a lens's distortion coefficients).
             {"one", "one", 1, "a dimensionless number"},
             // Joint compliance under gravity (models/joint_compliance.hpp): a revolute
             // joint's compliance, a prismatic one's, a fitted moment (compliance times a
             // weight, per metre of lever), and the payload's mass.
             {"rad/Nm", "rad/Nm", 1, "a joint compliance"},
             {"mm/N", "mm/N", 1, "a linear compliance"},
             {"rad/m", "rad/m", 1, "a compliance times a weight"},
             {"kg", "kg", 1, "a mass"},
             {"g", "kg", 1e-3, "a mass"}} {}

UnitRegistry& UnitRegistry::global() {
  static UnitRegistry registry;
  return registry;
}

void UnitRegistry::add_base(const std::string& name, const std::string& quantity) {
  if (!is_unit_name(name))
    throw std::invalid_argument("unit '" + name +
                                "': expected a name of letters only (at most 16)");
  const std::lock_guard<std::mutex> lock(registry_mutex());
  for (const Unit& u : units_)
    if (u.name == name) throw std::invalid_argument("unit '" + name + "' is already known");
  units_.push_back({name, name, 1, quantity});
}

void UnitRegistry::add_alias(const std::string& name, const std::string& base, double factor) {
  if (!is_unit_name(name))
    throw std::invalid_argument("unit '" + name +
                                "': expected a name of letters only (at most 16)");
  if (!(factor > 0) || !std::isfinite(factor))
    throw std::invalid_argument("unit '" + name + "': expected a finite conversion factor > 0");
  const std::lock_guard<std::mutex> lock(registry_mutex());
  const Unit* to = nullptr;
  for (const Unit& u : units_) {
    if (u.name == name) throw std::invalid_argument("unit '" + name + "' is already known");
    if (u.name == base && u.base == base) to = &u;
  }
  if (!to) throw std::invalid_argument("unit '" + name + "': '" + base + "' is not a base unit");
  const std::string quantity = to->quantity;
  units_.push_back({name, base, factor, quantity});
}

bool UnitRegistry::find(const std::string& name, Unit* unit) const {
  const std::lock_guard<std::mutex> lock(registry_mutex());
  for (const Unit& u : units_)
    if (u.name == name) {
      if (unit) *unit = u;
      return true;
    }
  return false;
}

std::vector<std::string> UnitRegistry::names() const {
  const std::lock_guard<std::mutex> lock(registry_mutex());
  std::vector<std::string> out;
  for (const Unit& u : units_) out.push_back(u.name);
  return out;
}

std::vector<std::string> UnitRegistry::units_of(const std::string& base) const {
  const std::lock_guard<std::mutex> lock(registry_mutex());
  std::vector<std::string> out;
  for (const Unit& u : units_)
    if (u.base == base && u.name == base)
      out.insert(out.begin(), u.name);
    else if (u.base == base)
      out.push_back(u.name);
  return out;
}

bool is_known_unit(const std::string& unit) {
  Unit u;
  return UnitRegistry::global().find(unit, &u) && u.base == u.name;
}

double wrap_angle(double radians) {
  if (!std::isfinite(radians)) return radians;
  double wrapped = std::remainder(radians, 2 * kPi);  // in [-pi, pi]
  if (wrapped <= -kPi) wrapped += 2 * kPi;
  return wrapped;
}

UnitValues UnitValues::parse(const std::string& text) {
  UnitValues out;
  std::string::size_type start = 0;
  while (true) {
    const auto comma = text.find(',', start);
    const std::string part = text.substr(start, comma - start);
    const char* begin = part.c_str();
    char* end = nullptr;
    const double value = std::strtod(begin, &end);
    std::string name(end);
    if (part.empty() || end == begin || !std::isfinite(value))
      throw std::invalid_argument("'" + part + "' is not a number with a unit (e.g. 5mm, 0.01rad)");
    if (name.empty()) name = kMillimetre;
    Unit unit;
    if (!UnitRegistry::global().find(name, &unit)) {
      std::string known;
      for (const auto& n : UnitRegistry::global().names()) known += (known.empty() ? "" : ", ") + n;
      throw std::invalid_argument("'" + part + "': unknown unit '" + name + "' (expected one of " +
                                  known + ")");
    }
    if (out.has(unit.base))
      throw std::invalid_argument("'" + text + "' gives a value in " + unit.base + " twice");
    out.set(unit.base, value * unit.factor);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

double UnitValues::get(const std::string& unit, double fallback) const {
  const auto it = values_.find(unit);
  return it == values_.end() ? fallback : it->second;
}

bool UnitValues::any_positive() const {
  for (const auto& [unit, value] : values_)
    if (value > 0) return true;
  return false;
}

UnitValues UnitValues::over(const UnitValues& defaults) const {
  UnitValues out = defaults;
  for (const auto& [unit, value] : values_) out.set(unit, value);
  return out;
}

UnitValues UnitValues::scaled(double factor) const {
  UnitValues out;
  for (const auto& [unit, value] : values_) out.set(unit, value * factor);
  return out;
}

std::string UnitValues::to_string() const {
  std::string out;
  for (const auto& [unit, value] : values_) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g %s", value, unit.c_str());
    out += (out.empty() ? "" : ", ") + std::string(buf);
  }
  return out;
}

}  // namespace kincal
