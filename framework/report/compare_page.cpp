// The page of a comparison with a known truth (compare_html, pages.hpp).

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "kincal/framework/report/html_page.hpp"
#include "kincal/framework/report/pages.hpp"

namespace kincal::report {

namespace {

using L = Finding::Level;

}  // namespace

std::string compare_html(const CompareResult& c) {
  const PoseErrors& pose = c.pose;
  const double p_mean = pose.position_mean, p_max = pose.position_max,
               o_mean = pose.orientation_mean;
  const std::string where =
      c.from_data ? "the " + fmt(c.configurations, 6) + " configurations of " + c.data_file
                  : fmt(c.configurations, 6) + " configurations drawn in the workspace";
  std::vector<Finding> verdicts;
  if (std::isfinite(p_mean) && std::isfinite(p_max) && std::isfinite(o_mean))
    verdicts.push_back({"pose", L::kNote,
                        "Against the truth, the model's pose is off by " + fmt(p_mean, 4) +
                            " mm on average (at most " + fmt(p_max, 4) + " mm) and " +
                            fmt(o_mean, 4) + " rad in orientation, over " + where + ".",
                        "Compare with the nominal model against the same truth to see what "
                        "the calibration gained."});
  else
    verdicts.push_back({"pose", L::kDoNotLoad, "The pose errors are missing or not numbers.", ""});
  const double failures = pose.fk_failures;
  if (failures > 0)
    verdicts.push_back({"unreachable", L::kWarning,
                        fmt(failures, 6) +
                            " configurations are unreachable by the truth or the model; they "
                            "are left out of the figures.",
                        ""});

  HtmlPage page("kincal compare: " + c.model_file + " against " + c.truth_file);
  page.add_section("verdicts", "Verdicts", findings_html(verdicts));

  // Pose errors: a summary table and the position error per configuration.
  std::string pose_html =
      "<p>Over " + esc(where) +
      ".</p><table><tr><th class=\"name\"></th><th>mean</th><th>RMS</th><th>max</th></tr>";
  pose_html += "<tr><td class=\"name\">position (mm)</td><td>" + fmt(p_mean) + "</td><td>" +
               fmt(pose.position_rms) + "</td><td>" + fmt(p_max) + "</td></tr>";
  pose_html += "<tr><td class=\"name\">orientation (rad)</td><td>" + fmt(o_mean) + "</td><td>" +
               fmt(pose.orientation_rms) + "</td><td>" + fmt(pose.orientation_max) +
               "</td></tr></table>";
  if (!pose.position.empty()) {
    const std::vector<double>& per = pose.position;
    double top = 0;
    for (double v : per)
      if (std::isfinite(v)) top = std::max(top, v);
    SvgChart chart(1000, 300, "Position error per configuration (mm)");
    chart.set_x({0, static_cast<double>(per.size()) + 1, false, "configuration"});
    chart.set_y({0, top > 0 ? top * 1.1 : 1, false, "position error (mm)"});
    chart.draw_axes();
    for (std::size_t i = 0; i < per.size(); ++i) {
      const double v = per[i];
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
  std::map<std::string, std::vector<const ParameterError*>> by_unit;
  for (const auto& p : c.parameters) by_unit[p.unit].push_back(&p);
  for (const auto& [unit, list] : by_unit) {
    double extent = 0;
    for (const ParameterError* p : list) {
      const double e = p->error;
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
      const double y = static_cast<double>(list.size() - i), e = list[i]->error;
      const std::string& name = list[i]->name;
      chart.text_px(chart.left() - 4, chart.py(y) + 4, name, "label", "end");
      if (std::isfinite(e)) chart.point(e, y, 3.5, "est", name + ": " + fmt(e, 4) + " " + unit);
    }
    params_html += chart.str();
  }
  {
    params_html +=
        "<table><tr><th class=\"name\">unit</th><th>parameters</th><th>RMS error</th>"
        "<th>largest |error|</th><th class=\"name\">of</th></tr>";
    for (const auto& [unit, s] : c.by_unit)
      params_html += "<tr><td class=\"name\">" + esc(unit) + "</td><td>" + fmt(s.count, 6) +
                     "</td><td>" + fmt(s.rms) + "</td><td>" + fmt(s.max_abs) +
                     "</td><td class=\"name\">" + esc(s.max_abs_parameter) + "</td></tr>";
    params_html += "</table>";
  }
  params_html +=
      "<table><tr><th class=\"name\">parameter</th><th>unit</th><th>free</th><th>truth</th>"
      "<th>estimate</th><th>error</th></tr>";
  for (const auto& p : c.parameters)
    params_html += "<tr><td class=\"name\">" + esc(p.name) + "</td><td>" + esc(p.unit) +
                   "</td><td>" + (p.free ? "yes" : "no") + "</td><td>" + fmt(p.truth, 8) +
                   "</td><td>" + fmt(p.estimate, 8) + "</td><td>" + fmt(p.error) + "</td></tr>";
  params_html += "</table>";
  page.add_section("parameters", "Parameter errors against the truth", params_html);
  return page.str();
}

}  // namespace kincal::report
