#include "kincal/cli/html_sensitivity.hpp"

#include <algorithm>
#include <cmath>

#include "kincal/cli/svg_plot.hpp"

namespace kincal::cli {

namespace {

using Json = nlohmann::ordered_json;

double number_at(const Json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_number() ? j[key].get<double>() : NAN;
}
std::string text_at(const Json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : "";
}
std::string fmt(double v, int digits = 4) { return format_number(v, digits); }

// The error assumed, in the unit a person reads: rad as mrad.
std::string error_text(const Json& row) {
  const std::string unit = text_at(row, "unit");
  const double e = number_at(row, "error");
  return unit == "rad" ? fmt(e * 1000, 3) + " mrad" : fmt(e, 3) + " " + unit;
}

}  // namespace

std::string sensitivity_html(const Json& rows, double target_mm) {
  if (!rows.is_array() || rows.empty())
    return "<p>No fixed parameter: every parameter is calibrated, none can leave an error "
           "behind.</p>";
  std::string out =
      "<p>Each fixed parameter is put off by the error shown, the free ones are calibrated "
      "again from the same configurations, and what remains is the pose error below (first "
      "order). A large error that leaves small residuals is one calibration cannot see: "
      "measure that parameter another way, or free it.</p>";
  double top = std::isfinite(target_mm) ? target_mm : 0;
  for (const auto& row : rows) {
    const double v = number_at(row, "position_max_mm");
    if (std::isfinite(v)) top = std::max(top, v);
  }
  const int n = static_cast<int>(rows.size());
  SvgChart chart(1000, 30 + 46 + 18 * n, "Largest position error left by each fixed parameter",
                 190);
  chart.set_x({0, top > 0 ? top * 1.1 : 1, false, "position error after re-calibration, max (mm)"});
  chart.set_y({0.5, n + 0.5, false, ""});
  chart.draw_axes(true, false);
  for (int i = 0; i < n; ++i) {
    const Json& row = rows[static_cast<std::size_t>(i)];
    const double y = n - i, v = number_at(row, "position_max_mm");
    const std::string name = text_at(row, "name");
    chart.text_px(chart.left() - 4, chart.py(y) + 4, name, "label", "end");
    if (std::isfinite(v))
      chart.rect(0, y - 0.35, v, y + 0.35, "bar",
                 name + " off by " + error_text(row) + ": up to " + fmt(v, 4) + " mm");
  }
  if (std::isfinite(target_mm)) chart.line(target_mm, 0.5, target_mm, n + 0.5, "threshold");
  out += chart.str();
  out +=
      "<table><tr><th class=\"name\">fixed parameter</th><th>error assumed</th>"
      "<th>residual RMS (readings)</th><th>position mean (mm)</th><th>position max (mm)</th>"
      "<th>orientation mean (mrad)</th><th>orientation max (mrad)</th></tr>";
  for (const auto& row : rows)
    out += "<tr><td class=\"name\">" + xml_escape(text_at(row, "name")) + "</td><td>" +
           xml_escape(error_text(row)) + "</td><td>" + fmt(number_at(row, "residual_rms"), 3) +
           "</td><td>" + fmt(number_at(row, "position_mean_mm")) + "</td><td>" +
           fmt(number_at(row, "position_max_mm")) + "</td><td>" +
           fmt(number_at(row, "orientation_mean_rad") * 1000) + "</td><td>" +
           fmt(number_at(row, "orientation_max_rad") * 1000) + "</td></tr>";
  return out + "</table>";
}

}  // namespace kincal::cli
