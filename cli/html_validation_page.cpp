// The page of `kincal validate --html` (cli/html_pages.hpp).

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "kincal/cli/html_pages.hpp"
#include "kincal/cli/html_pose_accuracy.hpp"
#include "kincal/cli/html_report.hpp"
#include "kincal/cli/html_values.hpp"
#include "kincal/cli/svg_plot.hpp"

namespace kincal::cli {

namespace {

using namespace html_values;
using L = Verdict::Level;

std::vector<Verdict> validation_verdicts(const Json& v) {
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
  if (const auto target = target_verdict(v.contains("target") ? v["target"] : Json()))
    verdicts.push_back(*target);
  if (v.contains("pose_accuracy_shown") && v["pose_accuracy_shown"] == false)
    verdicts.push_back({L::kNote,
                        "These readings measure no point of the mechanism: agreeing with them "
                        "does not confirm its pose accuracy.",
                        "To check the pose, validate on configurations measured with a point or "
                        "pose tracker, or with the gauge in a second placement."});
  if (verdict != "not_tested" &&
      !(v.contains("parameter_uncertainty") && v["parameter_uncertainty"] == true))
    verdicts.push_back({L::kNote,
                        "The prediction is the noise alone: the parameters are taken as exact.",
                        "Give the calibration's report (--report) to include their uncertainty."});
  return verdicts;
}

std::string summary_html(const Json& v) {
  std::string out = "<table>";
  auto row = [&](const std::string& key, const std::string& value) {
    out += "<tr><th class=\"name\">" + esc(key) + "</th><td class=\"name\">" + esc(value) +
           "</td></tr>";
  };
  row("model", text_at(v, "model"));
  row("held-out data", text_at(v, "data"));
  row("calibration report",
      v.contains("report") && v["report"].is_string() ? v["report"].get<std::string>() : "none");
  row("configurations", fmt(number_at(v, "configurations"), 9) + " (" +
                            fmt(number_at(v, "readings"), 9) + " readings)");
  const std::string noise = text_at(v, "noise");
  row("prediction",
      noise.empty() ? "none (no report, no reading_std)"
                    : "noise " + noise +
                          (v.contains("parameter_uncertainty") && v["parameter_uncertainty"] == true
                               ? " + the parameters' uncertainty"
                               : " alone"));
  if (std::isfinite(number_at(v, "chi_square")))
    row("chi-square", fmt(number_at(v, "chi_square")) + " on " +
                          fmt(number_at(v, "degrees_of_freedom"), 9) +
                          " degrees of freedom: P(larger) " + fmt(number_at(v, "p_larger"), 3) +
                          ", P(smaller) " + fmt(number_at(v, "p_smaller"), 3) + " (significance " +
                          fmt(number_at(v, "significance"), 3) + ")");
  return out + "</table>";
}

std::string per_reading_html(const Json& v) {
  if (!v.contains("per_reading") || !v["per_reading"].is_array()) return "";
  std::string out =
      "<table><tr><th class=\"name\">reading</th><th>unit</th><th>readings</th><th>RMS</th>"
      "<th>max</th><th>predicted RMS</th><th>of which noise</th><th>of which parameters</th>"
      "</tr>";
  for (const auto& p : v["per_reading"])
    out += "<tr><td class=\"name\">" + esc(text_at(p, "name")) + "</td><td>" +
           esc(text_at(p, "unit")) + "</td><td>" + fmt(number_at(p, "readings"), 9) + "</td><td>" +
           fmt(number_at(p, "rms")) + "</td><td>" + fmt(number_at(p, "max")) + "</td><td>" +
           fmt(number_at(p, "predicted_rms")) + "</td><td>" + fmt(number_at(p, "noise_std")) +
           "</td><td>" + fmt(number_at(p, "parameter_rms")) + "</td></tr>";
  return out + "</table>";
}

// One chart per unit: each reading's residual per configuration, +- its predicted RMS.
std::string residual_charts_html(const Json& v) {
  const Json& rows = v.contains("residuals") ? v["residuals"] : Json();
  if (!rows.is_array() || rows.empty() || !v.contains("per_reading")) return "";
  std::map<std::string, std::vector<const Json*>> by_unit;
  for (const auto& p : v["per_reading"]) by_unit[text_at(p, "unit")].push_back(&p);
  std::string out;
  for (const auto& [unit, readings] : by_unit) {
    double extent = 0;
    for (const auto& row : rows)
      for (const Json* p : readings) {
        const double r = number_at(row, text_at(*p, "name"));
        if (std::isfinite(r)) extent = std::max(extent, std::abs(r));
      }
    for (const Json* p : readings) {
      const double band = number_at(*p, "predicted_rms");
      if (std::isfinite(band)) extent = std::max(extent, band);
    }
    extent = extent > 0 ? extent * 1.1 : 1;
    const double last = rows.size() + 1.0;
    SvgChart chart(1000, 300,
                   "Held-out residual (predicted - measured) per configuration, " + unit);
    chart.set_x({0, last, false, "configuration (in file order)"});
    chart.set_y({-extent, extent, false, "residual (" + unit + ")"});
    chart.draw_axes();
    chart.line(0, 0, last, 0, "zero");
    double legend_x = chart.left() + 6;
    for (std::size_t k = 0; k < readings.size(); ++k) {
      const std::string name = text_at(*readings[k], "name");
      const std::string css = "s" + std::to_string(k % 6);
      const double band = number_at(*readings[k], "predicted_rms");
      if (std::isfinite(band))
        for (double sign : {-1.0, 1.0}) chart.line(0, sign * band, last, sign * band, "noise");
      for (std::size_t c = 0; c < rows.size(); ++c) {
        const double r = number_at(rows[c], name);
        if (std::isfinite(r))
          chart.point(c + 1.0, r, 2.6, css,
                      "line " + fmt(number_at(rows[c], "line"), 9) + ", " + name + ": " +
                          fmt(r, 4) + " " + unit);
      }
      chart.text_px(legend_x, chart.top() + 12, "\xE2\x97\x8F " + name, "legend " + css);
      legend_x += 24 + 7.0 * name.size();
    }
    chart.text_px(chart.right(), chart.top() - 6, "green dashed: \xC2\xB1predicted RMS", "legend",
                  "end");
    out += chart.str();
  }
  return out;
}

// The 3-D position error per configuration with the model before calibration and after.
std::string before_after_html(const Json& v) {
  const Json& rows = v.contains("residuals") ? v["residuals"] : Json();
  bool any = false, before = false;
  double top = number_at(v.contains("target") ? v["target"] : Json(), "position_mm");
  top = std::isfinite(top) ? top : 0;
  if (rows.is_array())
    for (const auto& row : rows) {
      for (const char* key : {"position_error_mm", "position_error_before_mm"}) {
        const double e = number_at(row, key);
        if (std::isfinite(e)) top = std::max(top, e);
      }
      any = any || std::isfinite(number_at(row, "position_error_mm"));
      before = before || std::isfinite(number_at(row, "position_error_before_mm"));
    }
  std::string out;
  const Json& p = v.contains("position_error_mm") ? v["position_error_mm"] : Json();
  if (p.is_object()) {
    out +=
        "<table><tr><th class=\"name\">model</th><th>points</th><th>mean (mm)</th>"
        "<th>RMS (mm)</th><th>max (mm)</th><th class=\"name\">file</th></tr>";
    for (const char* which : {"before", "after"}) {
      if (!p.contains(which) || !p[which].is_object()) continue;
      const Json& s = p[which];
      out += "<tr><td class=\"name\">" + std::string(which) + "</td><td>" +
             fmt(number_at(s, "points"), 9) + "</td><td>" + fmt(number_at(s, "mean")) +
             "</td><td>" + fmt(number_at(s, "rms")) + "</td><td>" + fmt(number_at(s, "max")) +
             "</td><td class=\"name\">" + esc(text_at(p, (std::string(which) + "_model").c_str())) +
             "</td></tr>";
    }
    out += "</table>";
  }
  if (!any) return out;
  const double last = rows.size() + 1.0;
  SvgChart chart(1000, 300, "3-D position error of the measured point per configuration");
  chart.set_x({0, last, false, "configuration (in file order)"});
  chart.set_y({0, top > 0 ? top * 1.1 : 1, false, "position error (mm)"});
  chart.draw_axes();
  for (std::size_t c = 0; c < rows.size(); ++c) {
    const std::string line = fmt(number_at(rows[c], "line"), 9);
    const double b = number_at(rows[c], "position_error_before_mm"),
                 a = number_at(rows[c], "position_error_mm");
    if (std::isfinite(b))
      chart.point(c + 1.0, b, 2.6, "s3", "line " + line + ", before: " + fmt(b, 4) + " mm");
    if (std::isfinite(a))
      chart.point(c + 1.0, a, 2.6, "s0", "line " + line + ", after: " + fmt(a, 4) + " mm");
  }
  chart.text_px(chart.left() + 6, chart.top() + 12, "\xE2\x97\x8F after (calibrated)", "legend s0");
  if (before)
    chart.text_px(chart.left() + 170, chart.top() + 12, "\xE2\x97\x8F before", "legend s3");
  const double target = number_at(v.contains("target") ? v["target"] : Json(), "position_mm");
  if (std::isfinite(target)) {
    chart.line(0, target, last, target, "threshold");
    chart.text(last - 0.5, target, "target " + fmt(target, 3) + " mm", "legend", "end");
  }
  return out + chart.str();
}

// Without a point: each reading's |residual| per configuration with the model before
// calibration and after ("before" in the rows: validate --report or --before).
std::string reading_before_after_html(const Json& v) {
  const Json& rows = v.contains("residuals") ? v["residuals"] : Json();
  if (!rows.is_array() || rows.empty() || !v.contains("per_reading")) return "";
  std::string out;
  std::map<std::string, std::vector<std::string>> by_unit;
  for (const auto& p : v["per_reading"]) by_unit[text_at(p, "unit")].push_back(text_at(p, "name"));
  for (const auto& [unit, names] : by_unit) {
    double top = 0;
    bool any = false;
    for (const auto& row : rows)
      for (const auto& name : names) {
        const Json& before = row.contains("before") ? row["before"] : Json();
        for (double r : {number_at(row, name), number_at(before, name)})
          if (std::isfinite(r)) top = std::max(top, std::abs(r));
        any = any || std::isfinite(number_at(before, name));
      }
    if (!any) continue;
    const double last = rows.size() + 1.0;
    SvgChart chart(1000, 300, "Held-out |residual| before and after calibration, " + unit);
    chart.set_x({0, last, false, "configuration (in file order)"});
    chart.set_y({0, top > 0 ? top * 1.1 : 1, false, "|predicted - measured| (" + unit + ")"});
    chart.draw_axes();
    for (std::size_t c = 0; c < rows.size(); ++c) {
      const std::string line = fmt(number_at(rows[c], "line"), 9);
      const Json& before = rows[c].contains("before") ? rows[c]["before"] : Json();
      for (const auto& name : names) {
        const double b = number_at(before, name), a = number_at(rows[c], name);
        if (std::isfinite(b))
          chart.point(c + 1.0, std::abs(b), 2.6, "s3",
                      "line " + line + ", " + name + " before: " + fmt(b, 4) + " " + unit);
        if (std::isfinite(a))
          chart.point(c + 1.0, std::abs(a), 2.6, "s0",
                      "line " + line + ", " + name + " after: " + fmt(a, 4) + " " + unit);
      }
    }
    chart.text_px(chart.left() + 6, chart.top() + 12, "\xE2\x97\x8F after (calibrated)",
                  "legend s0");
    chart.text_px(chart.left() + 170, chart.top() + 12, "\xE2\x97\x8F before", "legend s3");
    out += chart.str();
  }
  return out;
}

}  // namespace

std::string render_validation_html(const Json& v) {
  HtmlPage page("kincal validate: " + text_at(v, "model") + " on " + text_at(v, "data"));
  page.add_section("verdicts", "Verdicts", verdicts_html(validation_verdicts(v)));
  page.add_section("summary", "Summary", summary_html(v));
  page.add_section("readings", "Residuals per reading against the prediction", per_reading_html(v));
  page.add_section("residuals", "Residuals per configuration", residual_charts_html(v));
  if (v.contains("pose_accuracy_shown") && v["pose_accuracy_shown"] == false)
    page.add_section("position", "Before and after calibration",
                     reading_before_after_html(v) + "<p>No 3-D position error: " +
                         esc(text_at(v, "pose_accuracy_note")) + ".</p>");
  else
    page.add_section("position", "3-D position error before and after calibration",
                     before_after_html(v));
  return page.str();
}

}  // namespace kincal::cli
