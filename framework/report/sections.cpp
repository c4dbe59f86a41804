#include "kincal/framework/report/sections.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "kincal/framework/report/html_page.hpp"

namespace kincal::report {

std::string identifiability_html(const Identifiability& id) {
  if (id.singular_values.size() == 0) return "<p>No identifiability analysis.</p>";
  std::vector<double> s;
  for (int i = 0; i < id.singular_values.size(); ++i)
    s.push_back(finite_or_nan(id.singular_values[i]));
  const double threshold = id.numerical_threshold;
  const double s1 = s[0];
  if (!(s1 > 0) || !std::isfinite(s1))
    return "<p>The identification Jacobian is zero or not finite: no reading depends on the "
           "free parameters.</p>";
  double lo = s1;
  for (double v : s)
    if (v > 0 && std::isfinite(v)) lo = std::min(lo, v);
  if (std::isfinite(threshold) && threshold > 0) lo = std::min(lo, threshold);
  lo = std::pow(10.0, std::floor(std::log10(lo)));
  const double hi = std::pow(10.0, std::ceil(std::log10(s1 > 0 ? s1 : 1)));
  SvgChart chart(1000, 300, "Singular values of the scaled identification Jacobian");
  chart.set_x({0, s.size() + 1.0, false, "index (strongest to weakest direction)"});
  chart.set_y({lo, hi, true, "singular value"});
  chart.draw_axes();
  if (std::isfinite(threshold) && threshold > 0) {
    chart.line(0, threshold, s.size() + 1.0, threshold, "threshold");
    chart.text(s.size() + 0.8, threshold, "numerical rank threshold", "legend", "end");
  }
  // The analysis' own level for "weakly determined" (IdentifiabilityOptions::weak_ratio).
  const double weak = IdentifiabilityOptions().weak_ratio * s1;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double v = s[i] > 0 ? s[i] : lo;
    const char* css = s[i] < threshold ? "sv-null" : s[i] < weak ? "sv-weak" : "sv";
    chart.point(i + 1.0, v, 3.5, css, "s" + std::to_string(i + 1) + " = " + fmt(s[i], 4));
  }
  std::string out = chart.str();
  const double cond = finite_or_nan(id.condition_number);
  const int n = id.num_parameters;
  const int rank = id.numerical_rank;
  out += "<p>";
  if (rank < n)
    out += "The data determine " + std::to_string(rank) + " of " + std::to_string(n) +
           " directions: the red points are combinations of parameters the readings do not "
           "change. ";
  else
    out += "All " + std::to_string(n) + " free parameters are determined (full rank). ";
  if (std::isfinite(cond))
    out += "Condition number " + esc(fmt(cond, 3)) +
           ": the weakest direction is that many times less visible in the readings than the "
           "strongest, so noise along it is amplified that much. " +
           (cond < kIllConditioned ? "That is a well-conditioned calibration."
            : cond < kSeverelyIllConditioned
                ? "That is ill-conditioned: expect standard deviations far above the "
                  "sensor noise for the parameters in the weak directions."
                : "That is severely ill-conditioned: the weakest directions are close "
                  "to undeterminable.");
  out += " O1 " + esc(fmt(id.o1, 3)) + ", O2 " + esc(fmt(id.o2, 3)) + ", O3 " + esc(fmt(id.o3, 3)) +
         ", O4 " + esc(fmt(id.o4, 3)) + ", O5 " + esc(fmt(id.o5, 3)) + " (larger is better).</p>";
  if (!id.combinations.empty()) {
    out +=
        "<p>Weakest directions (moving the parameters along one changes the readings by "
        "almost nothing):</p><table><tr><th>kind</th><th>singular value</th>"
        "<th class=\"name\">combination</th></tr>";
    int shown = 0;
    for (const auto& c : id.combinations) {
      if (shown++ == 8) break;
      std::string terms;
      for (const auto& [name, k] : c.terms) terms += (k >= 0 ? " +" : " ") + fmt(k, 3) + " " + name;
      out += "<tr><td>" + esc(c.null_space ? "cannot be determined" : "weakly determined") +
             "</td><td>" + esc(fmt(c.singular_value, 3)) + "</td><td class=\"name\">" + esc(terms) +
             "</td></tr>";
    }
    out += "</table>";
  }
  return out;
}

namespace {

struct Quantity {
  double PoseErrorPrediction::*field;
  const char* label;
  double scale;  // rad are shown in mrad
};

const Quantity kQuantities[] = {
    {&PoseErrorPrediction::position_rms, "position, RMS over the workspace (mm)", 1},
    {&PoseErrorPrediction::position_mean_1sigma, "position, 1 sigma, mean over the workspace (mm)",
     1},
    {&PoseErrorPrediction::position_max_1sigma, "position, 1 sigma, worst configuration (mm)", 1},
    {&PoseErrorPrediction::position_mean_95,
     "position, 95 % quantile, mean over the workspace (mm)", 1},
    {&PoseErrorPrediction::position_max_95, "position, 95 % quantile, worst configuration (mm)", 1},
    {&PoseErrorPrediction::orientation_rms, "orientation, RMS over the workspace (mrad)", 1000},
    {&PoseErrorPrediction::orientation_mean_1sigma,
     "orientation, 1 sigma, mean over the workspace (mrad)", 1000},
    {&PoseErrorPrediction::orientation_max_1sigma,
     "orientation, 1 sigma, worst configuration (mrad)", 1000},
    {&PoseErrorPrediction::orientation_mean_95,
     "orientation, 95 % quantile, mean over the workspace (mrad)", 1000},
    {&PoseErrorPrediction::orientation_max_95,
     "orientation, 95 % quantile, worst configuration (mrad)", 1000},
};

}  // namespace

std::string pose_accuracy_html(int samples, const std::vector<PredictionColumn>& columns,
                               const TargetJudgement* target) {
  std::string out;
  out += "<p>The pose error expected from the parameters' uncertainty, at " + fmt(samples, 6) +
         " configurations drawn in the actuator box around home (1 sigma: the RMS of the "
         "error at a configuration; 95 %: the error exceeded with 5 % probability there).</p>";
  out += "<table class=\"pose-accuracy\"><tr><th class=\"name\">predicted error</th>";
  for (const auto& column : columns) out += "<th>" + esc(column.label) + "</th>";
  out += "</tr>";
  for (const Quantity& q : kQuantities) {
    out += "<tr><td class=\"name\">" + std::string(q.label) + "</td>";
    for (const auto& column : columns)
      out += "<td>" + fmt(finite_or_nan(column.prediction->*q.field) * q.scale, 4) + "</td>";
    out += "</tr>";
  }
  out += "</table>";

  // The error at every sampled configuration, sorted: how it spreads over the workspace.
  const double target_mm = target ? target->target.position_mm : NAN;
  std::vector<std::pair<std::string, std::vector<double>>> series;
  double top = std::isfinite(target_mm) ? target_mm : 0;
  for (const auto& column : columns) {
    std::vector<double> values;
    for (double v : column.prediction->position_1sigma)
      if (std::isfinite(v)) values.push_back(v);
    if (values.empty()) continue;
    std::sort(values.begin(), values.end());
    top = std::max(top, values.back());
    series.push_back({column.label, values});
  }
  if (series.empty()) return out + "<p>No per-configuration figures to plot.</p>";
  SvgChart chart(1000, 320, "Predicted position error (1 sigma) over the workspace, sorted");
  chart.set_x({0, 100, false, "share of the sampled workspace configurations (%), by error"});
  chart.set_y({0, top > 0 ? top * 1.1 : 1, false, "position error, 1 sigma (mm)"});
  chart.draw_axes();
  double legend_x = chart.left() + 6;
  for (std::size_t s = 0; s < series.size(); ++s) {
    const auto& [label, values] = series[s];
    const std::string css = "s" + std::to_string(s % 6);
    for (std::size_t i = 0; i < values.size(); ++i) {
      const double x = values.size() > 1 ? 100.0 * i / (values.size() - 1) : 50;
      chart.point(x, values[i], 2.2, css, label + ": " + fmt(values[i], 4) + " mm");
    }
    chart.text_px(legend_x, chart.top() + 12, "\xE2\x97\x8F " + label, "legend " + css);
    legend_x += 24 + 7.0 * label.size();
  }
  if (std::isfinite(target_mm)) {
    chart.line(0, target_mm, 100, target_mm, "threshold");
    chart.text(99, target_mm, "target " + fmt(target_mm, 3) + " mm", "legend", "end");
  }
  out += chart.str();
  if (std::isfinite(target_mm))
    out +=
        "<p>The red dashed line is your target; the verdict compares it with the 95 % "
        "quantile at the worst configuration, which is larger than the 1 sigma plotted.</p>";
  return out;
}

namespace {

// The error assumed, in the unit a person reads: rad as mrad.
std::string error_text(const FixedParameterSensitivity& row) {
  return row.unit == "rad" ? fmt(row.delta * 1000, 3) + " mrad"
                           : fmt(row.delta, 3) + " " + row.unit;
}

}  // namespace

std::string sensitivity_html(const SensitivityResult& sensitivity, double target_mm) {
  const auto& rows = sensitivity.rows;
  if (rows.empty())
    return "<p>No fixed parameter: every parameter is calibrated, none can leave an error "
           "behind.</p>";
  std::string out =
      "<p>Each fixed parameter is put off by the error shown, the free ones are calibrated "
      "again from the same configurations, and what remains is the pose error below (first "
      "order). A large error that leaves small residuals is one calibration cannot see: "
      "measure that parameter another way, or free it.</p>";
  double top = std::isfinite(target_mm) ? target_mm : 0;
  for (const auto& row : rows)
    if (std::isfinite(row.position_max)) top = std::max(top, row.position_max);
  const int n = static_cast<int>(rows.size());
  SvgChart chart(1000, 30 + 46 + 18 * n, "Largest position error left by each fixed parameter",
                 190);
  chart.set_x({0, top > 0 ? top * 1.1 : 1, false, "position error after re-calibration, max (mm)"});
  chart.set_y({0.5, n + 0.5, false, ""});
  chart.draw_axes(true, false);
  for (int i = 0; i < n; ++i) {
    const FixedParameterSensitivity& row = rows[static_cast<std::size_t>(i)];
    const double y = n - i, v = row.position_max;
    chart.text_px(chart.left() - 4, chart.py(y) + 4, row.name, "label", "end");
    if (std::isfinite(v))
      chart.rect(0, y - 0.35, v, y + 0.35, "bar",
                 row.name + " off by " + error_text(row) + ": up to " + fmt(v, 4) + " mm");
  }
  if (std::isfinite(target_mm)) chart.line(target_mm, 0.5, target_mm, n + 0.5, "threshold");
  out += chart.str();
  out +=
      "<table><tr><th class=\"name\">fixed parameter</th><th>error assumed</th>"
      "<th>residual RMS (readings)</th><th>position mean (mm)</th><th>position max (mm)</th>"
      "<th>orientation mean (mrad)</th><th>orientation max (mrad)</th></tr>";
  for (const auto& row : rows)
    out += "<tr><td class=\"name\">" + esc(row.name) + "</td><td>" + esc(error_text(row)) +
           "</td><td>" + fmt(row.residual_rms, 3) + "</td><td>" + fmt(row.position_mean) +
           "</td><td>" + fmt(row.position_max) + "</td><td>" + fmt(row.orientation_mean * 1000) +
           "</td><td>" + fmt(row.orientation_max * 1000) + "</td></tr>";
  return out + "</table>";
}

Finding target_finding(const TargetJudgement& target) {
  std::string text = target.verdict;
  if (!text.empty()) text[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(text[0])));
  text += ".";
  if (!target.meets) return {"target", Finding::Level::kNote, text, ""};
  if (*target.meets) return {"target", Finding::Level::kGood, text, ""};
  return {"target", Finding::Level::kDoNotLoad, text,
          "Measure more, or better chosen, configurations (kincal design --target "
          "predicts what a design reaches before you measure), add a sensor that "
          "measures the pose, or state what you know as prior_std."};
}

}  // namespace kincal::report
