#include "kincal/cli/html_pages.hpp"

#include <cmath>
#include <map>
#include <vector>

#include "kincal/cli/html_report.hpp"
#include "kincal/cli/svg_plot.hpp"

namespace kincal::cli {

namespace {

using Json = nlohmann::ordered_json;
using L = Verdict::Level;

double number_at(const Json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_number() ? j[key].get<double>() : NAN;
}

std::string text_at(const Json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : "";
}

std::string fmt(double v, int digits = 4) { return format_number(v, digits); }

}  // namespace

std::string render_validation_html(const Json& v) {
  std::vector<Verdict> verdicts;
  const std::string verdict = text_at(v, "verdict");
  const std::string stats = "standardized RMS " + fmt(number_at(v, "standardized_rms"), 3) +
                            " (1 = as predicted), P(larger) " + fmt(number_at(v, "p_larger"), 3);
  if (verdict == "not_tested")
    verdicts.push_back({L::kNote,
                        "Nothing predicts the residuals (no report, no reading_std): the errors "
                        "are shown, the consistency test is not made.",
                        "Give the calibration's report (--report) or state reading_std."});
  else if (verdict == "consistent")
    verdicts.push_back(
        {L::kGood, "The held-out residuals are what the calibration predicts: " + stats + ".", ""});
  else if (verdict == "larger_than_predicted")
    verdicts.push_back({L::kProblem,
                        "The held-out residuals are larger than predicted: " + stats +
                            ". The model misses something, or its uncertainty is understated.",
                        "Check the rows with the largest residuals, the fixed parameters "
                        "(kincal observability --sensitivity) and the stated reading_std."});
  else
    verdicts.push_back({L::kNote,
                        "The held-out residuals are smaller than predicted: " + stats +
                            ". The stated noise or uncertainty is pessimistic.",
                        ""});
  if (v.contains("position_error_mm") && v["position_error_mm"].is_object()) {
    const Json& p = v["position_error_mm"];
    const double after = p.contains("after") ? number_at(p["after"], "mean") : NAN;
    const double before =
        p.contains("before") && p["before"].is_object() ? number_at(p["before"], "mean") : NAN;
    if (std::isfinite(after) && std::isfinite(before))
      verdicts.push_back({after < before ? L::kGood : L::kProblem,
                          "Mean 3-D position error of the measured point: " + fmt(after, 4) +
                              " mm, against " + fmt(before, 4) + " mm before calibration.",
                          after < before ? ""
                                         : "The calibration made the machine less accurate "
                                           "on these data: check the data and the free "
                                           "parameters."});
    else if (std::isfinite(after))
      verdicts.push_back(
          {L::kNote, "Mean 3-D position error of the measured point: " + fmt(after, 4) + " mm.",
           "Give --report or --before to compare with the model before calibration."});
  }
  if (verdict != "not_tested" &&
      !(v.contains("parameter_uncertainty") && v["parameter_uncertainty"] == true))
    verdicts.push_back({L::kNote,
                        "The prediction is the noise alone: the parameters are taken as exact.",
                        "Give the calibration's report (--report) to include their uncertainty."});

  HtmlPage page("kincal validate: " + text_at(v, "model") + " on " + text_at(v, "data"));
  page.add_section("verdicts", "Verdicts", verdicts_html(verdicts));
  Json summary = Json::object();
  for (const char* key :
       {"model", "data", "report", "configurations", "readings", "noise", "standardized_rms",
        "chi_square", "degrees_of_freedom", "p_larger", "p_smaller", "significance", "verdict"})
    if (v.contains(key)) summary[key] = v[key];
  page.add_section("summary", "Summary", json_table_html(summary));
  if (v.contains("position_error_mm") && v["position_error_mm"].is_object()) {
    Json table = Json::array();
    for (const char* which : {"before", "after"}) {
      const Json& p = v["position_error_mm"];
      if (!p.contains(which) || !p[which].is_object()) continue;
      Json row = {{"model", which}};
      row.update(p[which]);
      table.push_back(row);
    }
    page.add_section("position", "3-D position error of the measured point (mm)",
                     json_table_html(table));
  }
  if (v.contains("per_reading"))
    page.add_section("readings", "Residuals per reading against the prediction",
                     json_table_html(v["per_reading"]));
  if (v.contains("residuals") && !v["residuals"].empty())
    page.add_section("residuals", "Residuals per configuration", json_table_html(v["residuals"]));
  return page.str();
}

std::string render_design_html(const Json& d) {
  const Json& predicted = d.contains("predicted_pose_error") ? d["predicted_pose_error"] : Json();
  auto rms = [&](const char* which) {
    return predicted.is_object() && predicted.contains(which)
               ? number_at(predicted[which], "position_rms_mm")
               : NAN;
  };
  const double designed = rms("designed"), random = rms("random"), nominal = rms("nominal");
  std::vector<Verdict> verdicts;
  if (std::isfinite(designed) && std::isfinite(random) && designed > 0)
    verdicts.push_back({designed < random ? L::kGood : L::kWarning,
                        "Predicted position error over the workspace: " + fmt(designed, 3) +
                            " mm RMS with this design, " + fmt(random, 3) +
                            " mm with random configurations of the same count (" +
                            fmt(random / designed, 3) + " times).",
                        ""});
  if (std::isfinite(designed) && std::isfinite(nominal))
    verdicts.push_back(
        designed < nominal
            ? Verdict{L::kGood,
                      "Calibrating from it is expected to beat the nominal model (" +
                          fmt(nominal, 3) + " mm RMS).",
                      "Measure the configurations of the template, fill in the readings, then "
                      "kincal calibrate."}
            : Verdict{L::kProblem,
                      "Even this design is not expected to beat the nominal model (" +
                          fmt(nominal, 3) + " mm RMS).",
                      "Add measurements (--poses), a second sensor placement, or what you know "
                      "as prior_std."});
  if (d.contains("noise_std_assumed") && d["noise_std_assumed"] == true)
    verdicts.push_back({L::kWarning,
                        "The reading noise was assumed (the model states no reading_std): the "
                        "absolute predictions scale with it.",
                        "State reading_std in the model, or give --noise-std."});

  if (d.contains("exchange") && d["exchange"].contains("bound")) {
    const double ratio = number_at(d["exchange"]["bound"], "std_ratio");
    if (std::isfinite(ratio))
      verdicts.push_back({ratio < 1.05 ? L::kGood : L::kNote,
                          "No design of " +
                              (d.contains("count") && d["count"].is_number_integer()
                                   ? std::to_string(d["count"].get<long long>())
                                   : std::string("this size")) +
                              " from these candidates can do more than " +
                              fmt(100 * (ratio - 1), 3) +
                              " % better than this one (a certified bound on the criterion, "
                              "converted to standard deviations).",
                          ratio < 1.05 ? "" : "More exchange passes or candidates may help."});
  }

  HtmlPage page("kincal design: " + text_at(d, "model"));
  page.add_section("verdicts", "Verdicts", verdicts_html(verdicts));
  Json summary = Json::object();
  for (const char* key : {"model", "criterion", "criterion_meaning", "count", "configurations",
                          "seed", "prior", "existing_readings", "template"})
    if (d.contains(key)) summary[key] = d[key];
  page.add_section("summary", "Summary", json_table_html(summary));
  if (predicted.is_object()) {
    // One row per quantity, one column per design.
    Json rows = Json::array();
    if (predicted.contains("designed"))
      for (const auto& [quantity, value] : predicted["designed"].items()) {
        Json row = {{"quantity", quantity}};
        for (const char* which : {"designed", "random", "nominal"})
          row[which] = predicted.contains(which) && predicted[which].contains(quantity)
                           ? predicted[which][quantity]
                           : Json();
        rows.push_back(row);
      }
    page.add_section("prediction", "Predicted pose error", json_table_html(rows));
  }
  if (d.contains("parameters"))
    page.add_section("parameters", "Predicted parameter std", json_table_html(d["parameters"]));
  // One row per figure: the nested objects flattened ("exchange passes", "bound value").
  Json search = Json::object();
  if (d.contains("candidates"))
    for (const auto& [key, value] : d["candidates"].items()) search["candidates " + key] = value;
  if (d.contains("exchange"))
    for (const auto& [key, value] : d["exchange"].items()) {
      if (key != "bound") {
        search["exchange " + key] = value;
        continue;
      }
      for (const auto& [b, v] : value.items()) search["bound " + b] = v;
    }
  page.add_section("search", "Candidates and exchange", json_table_html(search));
  return page.str();
}

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
