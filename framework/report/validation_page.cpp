// The page of a held-out validation (validation_html, pages.hpp).

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "kincal/framework/report/html_page.hpp"
#include "kincal/framework/report/pages.hpp"
#include "kincal/framework/report/sections.hpp"

namespace kincal::report {

namespace {

using L = Finding::Level;

// What the page reads of a validation, each figure as the report states it (NaN: not tested
// or not measured).
struct View {
  const ValidateRequest& request;
  const ValidateResult& result;
  const Validation& v;
  const std::optional<TargetJudgement>& target;
  std::vector<std::string> names;  // the model's readings: the residuals' columns

  double tested(double x) const { return result.tested ? finite_or_nan(x) : NAN; }
  // Residual of configuration c for the reading called `name`.
  double residual(const MatrixXd& m, int c, const std::string& name) const {
    const auto at = std::find(names.begin(), names.end(), name);
    return at == names.end() ? NAN : finite_or_nan(m(c, static_cast<int>(at - names.begin())));
  }
  bool has_before() const { return result.before_residuals.rows() == v.residuals.rows(); }
};

std::vector<Finding> validation_findings(const View& view) {
  const Validation& v = view.v;
  std::vector<Finding> verdicts;
  const std::string& verdict = v.verdict;
  const std::string stats = "standardized RMS " + fmt(view.tested(v.standardized_rms), 3) +
                            " (1 = as predicted), P(larger) " + fmt(view.tested(v.p_larger), 3);
  if (verdict == "not_tested")
    verdicts.push_back({"fit", L::kNote,
                        "Nothing predicts the residuals (no report, no reading_std): the errors "
                        "are shown, the consistency test is not made.",
                        "Give the calibration's report (--report) or state reading_std."});
  else if (verdict == "consistent")
    verdicts.push_back({"fit", L::kGood,
                        "The held-out residuals are what the calibration predicts: " + stats + ".",
                        ""});
  else if (verdict == "larger_than_predicted")
    verdicts.push_back({"fit", L::kDoNotLoad,
                        "The held-out residuals are larger than predicted: " + stats +
                            ". The model misses something, or its uncertainty is understated.",
                        "Check the rows with the largest residuals, the fixed parameters "
                        "(kincal observability --sensitivity) and the stated reading_std."});
  else
    verdicts.push_back({"fit", L::kNote,
                        "The held-out residuals are smaller than predicted: " + stats +
                            ". The stated noise or uncertainty is pessimistic.",
                        ""});
  const PositionComparison& p = view.result.position;
  if (p.computed) {
    const double after = finite_or_nan(p.after.mean);
    const double before = p.before_is.empty() ? NAN : finite_or_nan(p.before.mean);
    if (std::isfinite(after) && std::isfinite(before))
      verdicts.push_back({"position_error", after < before ? L::kGood : L::kDoNotLoad,
                          "Mean 3-D position error of the measured point: " + fmt(after, 4) +
                              " mm, against " + fmt(before, 4) + " mm before calibration.",
                          after < before ? ""
                                         : "The calibration made the machine less accurate "
                                           "on these data: check the data and the free "
                                           "parameters."});
    else if (std::isfinite(after))
      verdicts.push_back(
          {"position_error", L::kNote,
           "Mean 3-D position error of the measured point: " + fmt(after, 4) + " mm.",
           "Give --report or --before to compare with the model before calibration."});
  }
  if (view.target) verdicts.push_back(target_finding(*view.target));
  if (!view.result.shows_pose)
    verdicts.push_back({"pose_not_shown", L::kNote,
                        "These readings measure no point of the mechanism: agreeing with them "
                        "does not confirm its pose accuracy.",
                        "To check the pose, validate on configurations measured with a point or "
                        "pose tracker, or with the gauge in a second placement."});
  if (verdict != "not_tested" && !v.parameter_uncertainty)
    verdicts.push_back({"prediction", L::kNote,
                        "The prediction is the noise alone: the parameters are taken as exact.",
                        "Give the calibration's report (--report) to include their uncertainty."});
  return verdicts;
}

std::string summary_html(const View& view, const std::string& report_file) {
  const Validation& v = view.v;
  std::string out = "<table>";
  out += summary_row("model", view.request.model_file);
  out += summary_row("held-out data", view.request.data_file);
  out += summary_row("calibration report", report_file.empty() ? "none" : report_file);
  out += summary_row("configurations",
                     fmt(v.configurations, 9) + " (" + fmt(v.readings, 9) + " readings)");
  const std::string noise = view.result.tested ? view.request.prediction.noise_source : "";
  out += summary_row(
      "prediction",
      noise.empty() ? "none (no report, no reading_std)"
                    : "noise " + noise +
                          (v.parameter_uncertainty ? " + the parameters' uncertainty" : " alone"));
  const double chi_square = view.tested(v.chi_square);
  if (std::isfinite(chi_square))
    out += summary_row("chi-square", fmt(chi_square) + " on " + fmt(v.readings, 9) +
                                         " degrees of freedom: P(larger) " +
                                         fmt(view.tested(v.p_larger), 3) + ", P(smaller) " +
                                         fmt(view.tested(v.p_smaller), 3) + " (significance " +
                                         fmt(view.request.significance, 3) + ")");
  return out + "</table>";
}

std::string per_reading_html(const View& view) {
  const bool tested = view.result.tested;
  std::string out =
      "<table><tr><th class=\"name\">reading</th><th>unit</th><th>readings</th><th>RMS</th>"
      "<th>max</th><th>predicted RMS</th><th>of which noise</th><th>of which parameters</th>"
      "</tr>";
  for (const auto& p : view.v.per_reading)
    out += "<tr><td class=\"name\">" + esc(p.name) + "</td><td>" + esc(p.unit) + "</td><td>" +
           fmt(p.count, 9) + "</td><td>" + fmt(p.count ? p.rms : NAN) + "</td><td>" +
           fmt(p.count ? p.max : NAN) + "</td><td>" +
           fmt(p.count && tested ? p.predicted_rms : NAN) + "</td><td>" +
           fmt(tested ? p.noise_std : NAN) + "</td><td>" + fmt(p.count ? p.parameter_rms : NAN) +
           "</td></tr>";
  return out + "</table>";
}

double predicted_rms(const View& view, const ReadingValidation& p) {
  return p.count && view.result.tested ? p.predicted_rms : NAN;
}

// One chart per unit: each reading's residual per configuration, +- its predicted RMS.
std::string residual_charts_html(const View& view) {
  const MatrixXd& residuals = view.v.residuals;
  const int rows = static_cast<int>(residuals.rows());
  if (rows == 0) return "";
  std::map<std::string, std::vector<const ReadingValidation*>> by_unit;
  for (const auto& p : view.v.per_reading) by_unit[p.unit].push_back(&p);
  std::string out;
  for (const auto& [unit, readings] : by_unit) {
    double extent = 0;
    for (int c = 0; c < rows; ++c)
      for (const ReadingValidation* p : readings) {
        const double r = view.residual(residuals, c, p->name);
        if (std::isfinite(r)) extent = std::max(extent, std::abs(r));
      }
    for (const ReadingValidation* p : readings) {
      const double band = predicted_rms(view, *p);
      if (std::isfinite(band)) extent = std::max(extent, band);
    }
    extent = extent > 0 ? extent * 1.1 : 1;
    const double last = rows + 1.0;
    SvgChart chart(1000, 300,
                   "Held-out residual (predicted - measured) per configuration, " + unit);
    chart.set_x({0, last, false, "configuration (in file order)"});
    chart.set_y({-extent, extent, false, "residual (" + unit + ")"});
    chart.draw_axes();
    chart.line(0, 0, last, 0, "zero");
    double legend_x = chart.left() + 6;
    for (std::size_t k = 0; k < readings.size(); ++k) {
      const std::string& name = readings[k]->name;
      const std::string css = "s" + std::to_string(k % 6);
      const double band = predicted_rms(view, *readings[k]);
      if (std::isfinite(band))
        for (double sign : {-1.0, 1.0}) chart.line(0, sign * band, last, sign * band, "noise");
      for (int c = 0; c < rows; ++c) {
        const double r = view.residual(residuals, c, name);
        if (std::isfinite(r))
          chart.point(
              c + 1.0, r, 2.6, css,
              "line " + fmt(view.result.lines[c], 9) + ", " + name + ": " + fmt(r, 4) + " " + unit);
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
std::string before_after_html(const View& view) {
  const int rows = static_cast<int>(view.v.residuals.rows());
  const PositionComparison& p = view.result.position;
  const bool per_row =
      p.computed && p.after_errors.size() == static_cast<std::size_t>(view.v.residuals.rows());
  const bool per_row_before = per_row && p.before_errors.size() == p.after_errors.size();
  auto after_at = [&](int c) { return per_row ? finite_or_nan(p.after_errors[c]) : NAN; };
  auto before_at = [&](int c) { return per_row_before ? finite_or_nan(p.before_errors[c]) : NAN; };
  const double target = view.target ? view.target->target.position_mm : NAN;
  bool any = false, before = false;
  double top = std::isfinite(target) ? target : 0;
  for (int c = 0; c < rows; ++c) {
    for (double e : {after_at(c), before_at(c)})
      if (std::isfinite(e)) top = std::max(top, e);
    any = any || std::isfinite(after_at(c));
    before = before || std::isfinite(before_at(c));
  }
  std::string out;
  if (p.computed) {
    out +=
        "<table><tr><th class=\"name\">model</th><th>points</th><th>mean (mm)</th>"
        "<th>RMS (mm)</th><th>max (mm)</th><th class=\"name\">file</th></tr>";
    struct Which {
      const char* name;
      const PositionErrorStats* stats;
      std::string file;
    };
    const Which which[] = {{"before", p.before_is.empty() ? nullptr : &p.before, p.before_is},
                           {"after", &p.after, view.request.model_file}};
    for (const Which& w : which) {
      if (!w.stats) continue;
      out += "<tr><td class=\"name\">" + std::string(w.name) + "</td><td>" +
             fmt(w.stats->points, 9) + "</td><td>" + fmt(finite_or_nan(w.stats->mean)) +
             "</td><td>" + fmt(finite_or_nan(w.stats->rms)) + "</td><td>" +
             fmt(finite_or_nan(w.stats->max)) + "</td><td class=\"name\">" + esc(w.file) +
             "</td></tr>";
    }
    out += "</table>";
  }
  if (!any) return out;
  const double last = rows + 1.0;
  SvgChart chart(1000, 300, "3-D position error of the measured point per configuration");
  chart.set_x({0, last, false, "configuration (in file order)"});
  chart.set_y({0, top > 0 ? top * 1.1 : 1, false, "position error (mm)"});
  chart.draw_axes();
  for (int c = 0; c < rows; ++c) {
    const std::string line = fmt(view.result.lines[c], 9);
    const double b = before_at(c), a = after_at(c);
    if (std::isfinite(b))
      chart.point(c + 1.0, b, 2.6, "s3", "line " + line + ", before: " + fmt(b, 4) + " mm");
    if (std::isfinite(a))
      chart.point(c + 1.0, a, 2.6, "s0", "line " + line + ", after: " + fmt(a, 4) + " mm");
  }
  chart.text_px(chart.left() + 6, chart.top() + 12, "\xE2\x97\x8F after (calibrated)", "legend s0");
  if (before)
    chart.text_px(chart.left() + 170, chart.top() + 12, "\xE2\x97\x8F before", "legend s3");
  if (std::isfinite(target)) {
    chart.line(0, target, last, target, "threshold");
    chart.text(last - 0.5, target, "target " + fmt(target, 3) + " mm", "legend", "end");
  }
  return out + chart.str();
}

// Without a point: each reading's |residual| per configuration with the model before
// calibration and after (validate --report or --before).
std::string reading_before_after_html(const View& view) {
  const MatrixXd& residuals = view.v.residuals;
  const MatrixXd& before_residuals = view.result.before_residuals;
  const int rows = static_cast<int>(residuals.rows());
  if (rows == 0) return "";
  const bool has_before = view.has_before();
  std::string out;
  std::map<std::string, std::vector<std::string>> by_unit;
  for (const auto& p : view.v.per_reading) by_unit[p.unit].push_back(p.name);
  for (const auto& [unit, names] : by_unit) {
    double top = 0;
    bool any = false;
    for (int c = 0; c < rows; ++c)
      for (const auto& name : names) {
        const double b = has_before ? view.residual(before_residuals, c, name) : NAN;
        for (double r : {view.residual(residuals, c, name), b})
          if (std::isfinite(r)) top = std::max(top, std::abs(r));
        any = any || std::isfinite(b);
      }
    if (!any) continue;
    const double last = rows + 1.0;
    SvgChart chart(1000, 300, "Held-out |residual| before and after calibration, " + unit);
    chart.set_x({0, last, false, "configuration (in file order)"});
    chart.set_y({0, top > 0 ? top * 1.1 : 1, false, "|predicted - measured| (" + unit + ")"});
    chart.draw_axes();
    for (int c = 0; c < rows; ++c) {
      const std::string line = fmt(view.result.lines[c], 9);
      for (const auto& name : names) {
        const double b = has_before ? view.residual(before_residuals, c, name) : NAN,
                     a = view.residual(residuals, c, name);
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

// ISO 9283's figures (framework/analysis/iso9283.hpp) as tables: the summary, then one row
// per repeated configuration and per pair of consecutive ones.
std::string iso9283_html(const ValidateResult& result) {
  const Iso9283Stats& s = result.iso9283;
  const auto line = [&](int row) {
    return row < static_cast<int>(result.lines.size()) ? result.lines[static_cast<std::size_t>(row)]
                                                       : row + 1;
  };
  std::string out =
      "<p>The standard's command is the calibrated model's prediction at the commanded "
      "configuration: accuracy AP is how far the measurements' barycentre lies from it, "
      "repeatability RP = mean + 3 std of the distances from the barycentre";
  if (s.has_orientation)
    out += "; orientation a, b, c about the sensor's x, y, z as rotation-vector components";
  out +=
      " (docs: calibrating-a-machine.md, ISO 9283 statistics).</p><table><tr>"
      "<th>largest AP (mm)</th><th>largest RP (mm)</th>";
  if (!s.distances.empty()) out += "<th>largest |AD| (mm)</th><th>largest RD (mm)</th>";
  if (s.has_orientation) out += "<th>largest AP angle (rad)</th><th>largest RPa,b,c (rad)</th>";
  out += "</tr><tr><td>" + fmt(s.max_accuracy, 4) + "</td><td>" + fmt(s.max_repeatability, 4) +
         "</td>";
  if (!s.distances.empty())
    out += "<td>" + fmt(s.max_distance_accuracy, 4) + "</td><td>" +
           fmt(s.max_distance_repeatability, 4) + "</td>";
  if (s.has_orientation)
    out += "<td>" + fmt(s.max_orientation_accuracy, 4) + "</td><td>" +
           fmt(s.max_orientation_repeatability, 4) + "</td>";
  out +=
      "</tr></table><table><tr><th>first line</th><th>repeats</th><th>AP (mm)</th>"
      "<th>RP (mm)</th>";
  if (s.has_orientation)
    out += "<th>APa</th><th>APb</th><th>APc</th><th>RPa</th><th>RPb</th><th>RPc</th>";
  out += "</tr>";
  for (const Iso9283Pose& p : s.poses) {
    out += "<tr><td>" + std::to_string(line(p.first_row)) + "</td><td>" +
           std::to_string(p.repeats) + "</td><td>" + fmt(p.accuracy, 4) + "</td><td>" +
           fmt(p.repeatability, 4) + "</td>";
    if (p.has_orientation)
      for (const Vector3d* v : {&p.orientation_accuracy, &p.orientation_repeatability})
        for (int k = 0; k < 3; ++k) out += "<td>" + fmt((*v)[k], 3) + "</td>";
    out += "</tr>";
  }
  out += "</table>";
  if (!s.distances.empty()) {
    out +=
        "<table><tr><th>pair (first lines)</th><th>repeats</th><th>commanded (mm)</th>"
        "<th>AD (mm)</th><th>RD (mm)</th></tr>";
    for (const Iso9283Distance& d : s.distances)
      out +=
          "<tr><td>" + std::to_string(line(s.poses[static_cast<std::size_t>(d.first)].first_row)) +
          " &amp; " + std::to_string(line(s.poses[static_cast<std::size_t>(d.second)].first_row)) +
          "</td><td>" + std::to_string(d.repeats) + "</td><td>" + fmt(d.commanded, 6) +
          "</td><td>" + fmt(d.accuracy, 4) + "</td><td>" + fmt(d.repeatability, 4) + "</td></tr>";
    out += "</table>";
  }
  return out;
}

}  // namespace

std::string validation_html(const ValidateRequest& request, const ValidateResult& result,
                            const std::string& report_file,
                            const std::optional<TargetJudgement>& target) {
  const View view{request, result, result.validation, target, request.model->reading_names()};
  HtmlPage page("kincal validate: " + request.model_file + " on " + request.data_file);
  page.add_section("verdicts", "Verdicts", findings_html(validation_findings(view)));
  page.add_section("summary", "Summary", summary_html(view, report_file));
  page.add_section("readings", "Residuals per reading against the prediction",
                   per_reading_html(view));
  page.add_section("residuals", "Residuals per configuration", residual_charts_html(view));
  if (!result.shows_pose)
    page.add_section("position", "Before and after calibration",
                     reading_before_after_html(view) +
                         "<p>No 3-D position error: " + esc(kPoseNotShown) + ".</p>");
  else
    page.add_section("position", "3-D position error before and after calibration",
                     before_after_html(view));
  if (result.iso9283.computed())
    page.add_section("iso9283", "ISO 9283 pose accuracy and repeatability", iso9283_html(result));
  return page.str();
}

}  // namespace kincal::report
