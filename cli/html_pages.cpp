#include "kincal/cli/html_pages.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "kincal/cli/html_report.hpp"
#include "kincal/cli/html_values.hpp"
#include "kincal/cli/svg_plot.hpp"

namespace kincal::cli {

namespace {

using namespace html_values;
using L = Verdict::Level;

}  // namespace

std::string render_compare_html(const Json& c) {
  const auto esc = [](const std::string& t) { return xml_escape(t); };
  const Json& pose =
      c.contains("pose_error") && c["pose_error"].is_object() ? c["pose_error"] : Json::object();
  const double p_mean = number_at(pose, "position_mean_mm"),
               p_max = number_at(pose, "position_max_mm"),
               o_mean = number_at(pose, "orientation_mean_rad");
  const std::string where =
      text_at(pose, "source") == "data"
          ? "the " + fmt(number_at(pose, "configurations"), 6) + " configurations of " +
                text_at(pose, "data")
          : fmt(number_at(pose, "configurations"), 6) + " configurations drawn in the workspace";
  std::vector<Verdict> verdicts;
  if (std::isfinite(p_mean) && std::isfinite(p_max) && std::isfinite(o_mean))
    verdicts.push_back({L::kNote,
                        "Against the truth, the model's pose is off by " + fmt(p_mean, 4) +
                            " mm on average (at most " + fmt(p_max, 4) + " mm) and " +
                            fmt(o_mean, 4) + " rad in orientation, over " + where + ".",
                        "Compare with the nominal model against the same truth to see what "
                        "the calibration gained."});
  else
    verdicts.push_back({L::kProblem, "The pose errors are missing or not numbers.", ""});
  const double failures = number_at(pose, "fk_failures");
  if (std::isfinite(failures) && failures > 0)
    verdicts.push_back({L::kWarning,
                        fmt(failures, 6) +
                            " configurations are unreachable by the truth or the model; they "
                            "are left out of the figures.",
                        ""});

  HtmlPage page("kincal compare: " + text_at(c, "model") + " against " + text_at(c, "truth"));
  page.add_section("verdicts", "Verdicts", verdicts_html(verdicts));

  // Pose errors: a summary table and the position error per configuration.
  std::string pose_html =
      "<p>Over " + esc(where) +
      ".</p><table><tr><th class=\"name\"></th><th>mean</th><th>RMS</th><th>max</th></tr>";
  pose_html += "<tr><td class=\"name\">position (mm)</td><td>" + fmt(p_mean) + "</td><td>" +
               fmt(number_at(pose, "position_rms_mm")) + "</td><td>" + fmt(p_max) + "</td></tr>";
  pose_html += "<tr><td class=\"name\">orientation (rad)</td><td>" + fmt(o_mean) + "</td><td>" +
               fmt(number_at(pose, "orientation_rms_rad")) + "</td><td>" +
               fmt(number_at(pose, "orientation_max_rad")) + "</td></tr></table>";
  if (pose.contains("per_configuration") && pose["per_configuration"].is_array() &&
      !pose["per_configuration"].empty()) {
    const Json& per = pose["per_configuration"];
    double top = 0;
    for (const auto& row : per) {
      const double v = number_at(row, "position_mm");
      if (std::isfinite(v)) top = std::max(top, v);
    }
    SvgChart chart(1000, 300, "Position error per configuration (mm)");
    chart.set_x({0, static_cast<double>(per.size()) + 1, false, "configuration"});
    chart.set_y({0, top > 0 ? top * 1.1 : 1, false, "position error (mm)"});
    chart.draw_axes();
    for (std::size_t i = 0; i < per.size(); ++i) {
      const double v = number_at(per[i], "position_mm");
      if (std::isfinite(v))
        chart.point(static_cast<double>(i + 1), v, 2.6, "s0",
                    "configuration " + std::to_string(i + 1) + ": " + fmt(v, 4) + " mm");
    }
    pose_html += chart.str();
  }
  page.add_section("pose", "Pose error against the truth", pose_html);

  // Parameter errors: a plot per unit and the table.
  std::string params_html =
      "<p>Error = estimate - truth, for the parameters free in the model or whose values "
      "differ.</p>";
  const Json& params =
      c.contains("parameters") && c["parameters"].is_array() ? c["parameters"] : Json::array();
  std::map<std::string, std::vector<const Json*>> by_unit;
  for (const auto& p : params) by_unit[text_at(p, "unit")].push_back(&p);
  for (const auto& [unit, list] : by_unit) {
    double extent = 0;
    for (const Json* p : list) {
      const double e = number_at(*p, "error");
      if (std::isfinite(e)) extent = std::max(extent, std::abs(e));
    }
    extent = extent > 0 ? extent * 1.05 : 1;
    const int height = 30 + 46 + 18 * static_cast<int>(list.size());
    SvgChart chart(1000, height, "Parameter errors (" + unit + ")", 170);
    chart.set_x({-extent, extent, false, "estimate - truth (" + unit + ")"});
    chart.set_y({0.5, static_cast<double>(list.size()) + 0.5, false, ""});
    chart.draw_axes(true, false);
    chart.line(0, 0.5, 0, list.size() + 0.5, "zero");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const double y = static_cast<double>(list.size() - i), e = number_at(*list[i], "error");
      const std::string name = text_at(*list[i], "name");
      chart.text_px(chart.left() - 4, chart.py(y) + 4, name, "label", "end");
      if (std::isfinite(e)) chart.point(e, y, 3.5, "est", name + ": " + fmt(e, 4) + " " + unit);
    }
    params_html += chart.str();
  }
  if (c.contains("parameter_error") && c["parameter_error"].is_object()) {
    params_html +=
        "<table><tr><th class=\"name\">unit</th><th>parameters</th><th>RMS error</th>"
        "<th>largest |error|</th><th class=\"name\">of</th></tr>";
    for (const auto& [unit, s] : c["parameter_error"].items())
      params_html += "<tr><td class=\"name\">" + esc(unit) + "</td><td>" +
                     fmt(number_at(s, "count"), 6) + "</td><td>" + fmt(number_at(s, "rms")) +
                     "</td><td>" + fmt(number_at(s, "max_abs")) + "</td><td class=\"name\">" +
                     esc(text_at(s, "max_abs_parameter")) + "</td></tr>";
    params_html += "</table>";
  }
  params_html +=
      "<table><tr><th class=\"name\">parameter</th><th>unit</th><th>free</th><th>truth</th>"
      "<th>estimate</th><th>error</th></tr>";
  for (const auto& p : params)
    params_html += "<tr><td class=\"name\">" + esc(text_at(p, "name")) + "</td><td>" +
                   esc(text_at(p, "unit")) + "</td><td>" +
                   (p.contains("free") && p["free"] == true ? "yes" : "no") + "</td><td>" +
                   fmt(number_at(p, "truth"), 8) + "</td><td>" + fmt(number_at(p, "estimate"), 8) +
                   "</td><td>" + fmt(number_at(p, "error")) + "</td></tr>";
  params_html += "</table>";
  page.add_section("parameters", "Parameter errors against the truth", params_html);
  return page.str();
}

}  // namespace kincal::cli
