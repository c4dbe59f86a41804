#pragma once
// The page builder of the pages for people: one self-contained HTML file (no network, no
// script) with its styles, a table of contents and sections; the findings as a list; the
// small formatting helpers every page shares. Every string from a result (file, parameter
// and reading names, messages) goes through esc().

#include <cmath>
#include <string>
#include <vector>

#include "kincal/framework/analysis/calibration_verdict.hpp"
#include "kincal/framework/report/svg_plot.hpp"

namespace kincal::report {

/// A page: a head with the styles, sections appended in order.
class HtmlPage {
 public:
  explicit HtmlPage(std::string title);
  /// A section with an anchor id, a heading and HTML content (already escaped).
  void add_section(const std::string& id, const std::string& heading, const std::string& html);
  std::string str() const;

 private:
  std::string title_;
  std::vector<std::string> sections_, toc_;
};

/// Findings (the verdict's data, framework/analysis/calibration_verdict.hpp) as an HTML list:
/// each with its level (OK, Note, Warning, Problem for do-not-load), what was found and what
/// to do.
std::string findings_html(const std::vector<Finding>& findings);

inline std::string esc(const std::string& s) { return xml_escape(s); }
inline std::string fmt(double v, int digits = 4) { return format_number(v, digits); }
/// A figure as a report file carries it: a value that is not finite reads as NaN.
inline double finite_or_nan(double v) { return std::isfinite(v) ? v : NAN; }

/// A table row of a summary: the key as a header, the value as text.
std::string summary_row(const std::string& key, const std::string& value);

// Angles are stored in rad and shown in mrad: corrections of a few mrad read better.
struct DisplayUnit {
  std::string label;
  double scale = 1;
};
inline DisplayUnit display_unit(const std::string& unit) {
  if (unit == "rad") return {"mrad", 1000};
  return {unit, 1};
}

}  // namespace kincal::report
