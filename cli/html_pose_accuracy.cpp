#include "kincal/cli/html_pose_accuracy.hpp"

#include <algorithm>
#include <cmath>

#include "kincal/cli/svg_plot.hpp"

namespace kincal::cli {

namespace {

using Json = nlohmann::ordered_json;

double number_at(const Json& j, const std::string& key) {
  return j.is_object() && j.contains(key) && j[key].is_number() ? j[key].get<double>() : NAN;
}

std::string fmt(double v, int digits = 4) { return format_number(v, digits); }

struct Quantity {
  const char* key;
  const char* label;
  double scale;  // rad are shown in mrad
};

const Quantity kQuantities[] = {
    {"position_rms_mm", "position, RMS over the workspace (mm)", 1},
    {"position_mean_1sigma_mm", "position, 1 sigma, mean over the workspace (mm)", 1},
    {"position_max_1sigma_mm", "position, 1 sigma, worst configuration (mm)", 1},
    {"position_mean_95_mm", "position, 95 % quantile, mean over the workspace (mm)", 1},
    {"position_max_95_mm", "position, 95 % quantile, worst configuration (mm)", 1},
    {"orientation_rms_rad", "orientation, RMS over the workspace (mrad)", 1000},
    {"orientation_mean_1sigma_rad", "orientation, 1 sigma, mean over the workspace (mrad)", 1000},
    {"orientation_max_1sigma_rad", "orientation, 1 sigma, worst configuration (mrad)", 1000},
    {"orientation_mean_95_rad", "orientation, 95 % quantile, mean over the workspace (mrad)", 1000},
    {"orientation_max_95_rad", "orientation, 95 % quantile, worst configuration (mrad)", 1000},
};

}  // namespace

std::string pose_accuracy_html(const Json& predicted, const std::vector<PredictionColumn>& columns,
                               const Json& target) {
  if (!predicted.is_object()) return "<p>No predicted pose error.</p>";
  if (predicted.contains("computed") && predicted["computed"] == false)
    return "<p>Not computed: " +
           xml_escape(predicted.contains("why_not") && predicted["why_not"].is_string()
                          ? predicted["why_not"].get<std::string>()
                          : std::string("no reason given")) +
           ".</p>";
  std::string out;
  const double samples = number_at(predicted, "workspace_samples");
  out += "<p>The pose error expected from the parameters' uncertainty, at " + fmt(samples, 6) +
         " configurations drawn in the actuator box around home (1 sigma: the RMS of the "
         "error at a configuration; 95 %: the error exceeded with 5 % probability there).</p>";
  out += "<table class=\"pose-accuracy\"><tr><th class=\"name\">predicted error</th>";
  for (const auto& [key, label] : columns) out += "<th>" + xml_escape(label) + "</th>";
  out += "</tr>";
  for (const Quantity& q : kQuantities) {
    out += "<tr><td class=\"name\">" + std::string(q.label) + "</td>";
    for (const auto& [key, label] : columns) {
      const Json& column = predicted.contains(key) ? predicted[key] : Json();
      out += "<td>" + fmt(number_at(column, q.key) * q.scale, 4) + "</td>";
    }
    out += "</tr>";
  }
  out += "</table>";

  // The error at every sampled configuration, sorted: how it spreads over the workspace.
  const Json& per = predicted.contains("position_1sigma_mm_per_sample")
                        ? predicted["position_1sigma_mm_per_sample"]
                        : Json();
  const double target_mm = number_at(target, "position_mm");
  std::vector<std::pair<std::string, std::vector<double>>> series;
  double top = std::isfinite(target_mm) ? target_mm : 0;
  for (const auto& [key, label] : columns) {
    if (!per.is_object() || !per.contains(key) || !per[key].is_array()) continue;
    std::vector<double> values;
    for (const auto& v : per[key])
      if (v.is_number() && std::isfinite(v.get<double>())) values.push_back(v.get<double>());
    if (values.empty()) continue;
    std::sort(values.begin(), values.end());
    top = std::max(top, values.back());
    series.push_back({label, values});
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

std::string measured_position_error_html(const Json& r) {
  struct Row {
    std::string model, data;
    const Json* stats;
  };
  std::vector<Row> rows;
  const Json& p = r.contains("position_error_mm") ? r["position_error_mm"] : Json();
  const char* labels[][2] = {{"before", "before calibration (starting values)"},
                             {"registration_only", "registration only (frames fitted)"},
                             {"after", "calibrated"}};
  for (const auto& [key, label] : labels)
    if (p.is_object() && p.contains(key) && p[key].is_object())
      rows.push_back({label, "calibration data (in-sample)", &p[key]});
  const Json& cv = r.contains("cross_validation") ? r["cross_validation"] : Json();
  const std::string held_out =
      "held out, " + fmt(number_at(cv, "folds"), 3) + "-fold cross-validation";
  if (cv.is_object() && cv.contains("registration_only_position_error_mm") &&
      cv["registration_only_position_error_mm"].is_object())
    rows.push_back({"registration only (frames fitted)", held_out,
                    &cv["registration_only_position_error_mm"]});
  if (cv.is_object() && cv.contains("position_error_mm") && cv["position_error_mm"].is_object())
    rows.push_back({"calibrated", held_out, &cv["position_error_mm"]});
  if (rows.empty()) return "<p>No 3-D position error.</p>";
  std::string out =
      "<table><tr><th class=\"name\">model</th><th class=\"name\">data</th><th>points</th>"
      "<th>mean (mm)</th><th>RMS (mm)</th><th>max (mm)</th></tr>";
  double top = 0;
  for (const Row& row : rows) {
    out += "<tr><td class=\"name\">" + xml_escape(row.model) + "</td><td class=\"name\">" +
           xml_escape(row.data) + "</td><td>" + fmt(number_at(*row.stats, "points"), 9) +
           "</td><td>" + fmt(number_at(*row.stats, "mean")) + "</td><td>" +
           fmt(number_at(*row.stats, "rms")) + "</td><td>" + fmt(number_at(*row.stats, "max")) +
           "</td></tr>";
    for (const char* key : {"mean", "max"}) {
      const double v = number_at(*row.stats, key);
      if (std::isfinite(v)) top = std::max(top, v);
    }
  }
  out += "</table>";
  // Mean (bar) and max (tick) per row, first row at the top.
  const int n = static_cast<int>(rows.size());
  SvgChart chart(1000, 30 + 46 + 26 * n, "3-D position error of the measured point", 260);
  chart.set_x({0, top > 0 ? top * 1.1 : 1, false, "position error (mm): bar = mean, | = max"});
  chart.set_y({0.5, n + 0.5, false, ""});
  chart.draw_axes(true, false);
  for (int i = 0; i < n; ++i) {
    const Row& row = rows[static_cast<std::size_t>(i)];
    const double y = n - i, mean = number_at(*row.stats, "mean"),
                 max = number_at(*row.stats, "max");
    // Short labels beside the bars: the table has the long ones.
    const std::string label = row.model.substr(0, row.model.find(" (")) + ", " +
                              (row.data.rfind("held out", 0) == 0 ? "held out" : "in-sample");
    chart.text_px(chart.left() - 4, chart.py(y) + 4, label, "label", "end");
    if (std::isfinite(mean))
      chart.rect(0, y - 0.3, mean, y + 0.3, "bar",
                 row.model + ", " + row.data + ": mean " + fmt(mean, 4) + " mm");
    if (std::isfinite(max)) chart.line(max, y - 0.35, max, y + 0.35, "errbar");
  }
  out += chart.str();
  const Json& predicted =
      r.contains("predicted_point_error_mm") ? r["predicted_point_error_mm"] : Json();
  if (predicted.is_object())
    out += "<p>Predicted from the parameters' uncertainty at the " +
           fmt(number_at(predicted, "points"), 9) + " measured configurations: 1 sigma mean " +
           fmt(number_at(predicted, "mean_1sigma")) + " mm, worst " +
           fmt(number_at(predicted, "max_1sigma")) + " mm; 95 % quantile mean " +
           fmt(number_at(predicted, "mean_95")) + " mm, worst " +
           fmt(number_at(predicted, "max_95")) + " mm (RMS " + fmt(number_at(predicted, "rms")) +
           " mm).</p>";
  return out;
}

std::optional<Verdict> target_verdict(const Json& target) {
  if (!target.is_object()) return std::nullopt;
  std::string text = target.contains("verdict") && target["verdict"].is_string()
                         ? target["verdict"].get<std::string>()
                         : std::string("the target was not judged");
  if (!text.empty()) text[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(text[0])));
  text += ".";
  if (!target.contains("meets") || !target["meets"].is_boolean())
    return Verdict{Verdict::Level::kNote, text, ""};
  if (target["meets"].get<bool>()) return Verdict{Verdict::Level::kGood, text, ""};
  return Verdict{Verdict::Level::kProblem, text,
                 "Measure more, or better chosen, configurations (kincal design --target "
                 "predicts what a design reaches before you measure), add a sensor that "
                 "measures the pose, or state what you know as prior_std."};
}

}  // namespace kincal::cli
