#pragma once
// Small readers of a command's JSON for the pages for people (cli/html_report.cpp and the
// files of the calibration report's sections): a missing or mistyped field reads as NaN or
// "", never throws, so that a degenerate report still gives a page.

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "kincal/cli/html_report.hpp"
#include "kincal/cli/svg_plot.hpp"
#include "kincal/framework/base/angles.hpp"

namespace kincal::cli::html_values {

using Json = nlohmann::ordered_json;

inline double num(const Json& j) { return j.is_number() ? j.get<double>() : NAN; }
inline std::string text_of(const Json& j) {
  return j.is_string() ? j.get<std::string>() : j.is_null() ? "" : plain_text(j);
}
inline std::string text_of(const Json& j, const char* key) {
  return j.is_object() && j.contains(key) ? text_of(j[key]) : "";
}
inline const Json& member(const Json& j, const char* key) {
  static const Json null_value;
  return j.is_object() && j.contains(key) ? j[key] : null_value;
}

/// A number field, NaN when missing or not a number; a string field, "" when missing or not
/// a string (text_of writes any value as text instead).
inline double number_at(const Json& j, const std::string& key) {
  return j.is_object() && j.contains(key) ? num(j[key]) : NAN;
}
inline std::string text_at(const Json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : "";
}

inline std::string esc(const std::string& s) { return xml_escape(s); }
inline std::string fmt(double v, int digits = 4) { return format_number(v, digits); }

// Angles are stored in rad and shown in mrad: corrections of a few mrad read better.
struct DisplayUnit {
  std::string label;
  double scale = 1;
};
inline DisplayUnit display_unit(const std::string& unit) {
  if (unit == "rad") return {"mrad", 1000};
  return {unit, 1};
}

}  // namespace kincal::cli::html_values
