#include "kincal/framework/kinematics/units.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "kincal/framework/base/angles.hpp"

namespace kincal {

bool is_known_unit(const std::string& unit) { return unit == kMillimetre || unit == kRadian; }

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
    std::string unit(end);
    if (part.empty() || end == begin || !std::isfinite(value))
      throw std::invalid_argument("'" + part + "' is not a number with a unit (e.g. 5mm, 0.01rad)");
    if (unit.empty()) unit = kMillimetre;
    double scale = 1;
    if (unit == "deg") {
      unit = kRadian;
      scale = kRadiansPerDegree;
    }
    if (!is_known_unit(unit))
      throw std::invalid_argument("'" + part + "': unknown unit '" + unit +
                                  "' (expected mm, rad or deg)");
    if (out.has(unit))
      throw std::invalid_argument("'" + text + "' gives a value in " + unit + " twice");
    out.set(unit, value * scale);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

double UnitValues::get(const std::string& unit, double fallback) const {
  const auto it = values_.find(unit);
  return it == values_.end() ? fallback : it->second;
}

UnitValues UnitValues::over(const UnitValues& defaults) const {
  UnitValues out = defaults;
  for (const auto& [unit, value] : values_) out.set(unit, value);
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
