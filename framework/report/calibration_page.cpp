// The calibration report's page (calibration_page.hpp): its sections, each from the typed
// result.

#include "kincal/framework/report/calibration_page.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "kincal/framework/analysis/identifiability_words.hpp"
#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/report/html_page.hpp"
#include "kincal/framework/report/sections.hpp"

namespace kincal::report {

namespace {

// A count as the page has always written it (5 significant digits).
std::string count_text(double n) { return fmt(n, 5); }

// Residual c of reading k; NaN where not measured.
double residual(const CalibrationReport& r, int c, std::size_t k) {
  return finite_or_nan(r.residuals(c, static_cast<int>(k)));
}

// Residual groups: one chart per unit, or one in multiples of the stated std when weighted.
struct ResidualGroup {
  std::string label;                 // axis unit
  std::vector<std::size_t> indices;  // the readings
  std::vector<double> scale;         // divide residuals by this
  double noise = NAN;                // the +-band: sigma_hat in the group's unit
  double stated = NAN;               // the stated noise (weighted: 1)
  double threshold = NAN;            // outlier threshold in the group's unit
};

std::vector<ResidualGroup> residual_groups(const CalibrationReport& r) {
  std::vector<ResidualGroup> groups;
  const double sigma = finite_or_nan(r.uncertainty.sigma);
  const std::string unit_of_sigma = sigma_unit(r);
  if (r.weighted) {
    ResidualGroup g{"residual / reading_std", {}, {}, sigma, 1.0, r.outlier_threshold};
    for (std::size_t k = 0; k < r.reading_names.size(); ++k) {
      g.indices.push_back(k);
      const double s =
          r.reading_std.size() ? finite_or_nan(r.reading_std[static_cast<int>(k)]) : NAN;
      g.scale.push_back(std::isfinite(s) && s > 0 ? s : 1.0);
    }
    groups.push_back(g);
    return groups;
  }
  std::map<std::string, std::size_t> index;
  for (std::size_t k = 0; k < r.reading_names.size(); ++k) {
    const std::string& unit = r.reading_units[k];
    if (!index.count(unit)) {
      index[unit] = groups.size();
      const DisplayUnit du = display_unit(unit);
      // Each unit has its own threshold (outlier_threshold_by_unit).
      const auto own = r.outlier_threshold_by_unit.find(unit);
      groups.push_back(
          {du.label,
           {},
           {},
           unit_of_sigma == unit ? sigma * du.scale : NAN,
           NAN,
           (own != r.outlier_threshold_by_unit.end() ? own->second : r.outlier_threshold) *
               du.scale});
    }
    groups[index[unit]].indices.push_back(k);
    groups[index[unit]].scale.push_back(1.0 / display_unit(unit).scale);
  }
  return groups;
}

std::string residuals_html(const CalibrationReport& r) {
  const int rows = static_cast<int>(r.residuals.rows());
  if (rows == 0) return "<p>No residuals (they could not be computed).</p>";
  std::string out;
  for (const ResidualGroup& g : residual_groups(r)) {
    std::vector<double> values;
    double extent = 0;
    for (int c = 0; c < rows; ++c)
      for (std::size_t k = 0; k < g.indices.size(); ++k) {
        const double v = residual(r, c, g.indices[k]) / g.scale[k];
        if (std::isfinite(v)) {
          values.push_back(v);
          extent = std::max(extent, std::abs(v));
        }
      }
    if (values.empty()) continue;
    for (double band : {g.noise, g.threshold})
      if (std::isfinite(band)) extent = std::max(extent, band);
    extent = extent > 0 ? extent * 1.1 : 1;

    SvgChart scatter(1000, 300, "Residual (predicted - measured) per configuration");
    scatter.set_x({0, static_cast<double>(rows + 1), false, "configuration (in file order)"});
    scatter.set_y({-extent, extent, false, g.label});
    scatter.draw_axes();
    scatter.line(0, 0, rows + 1.0, 0, "zero");
    const double last = rows + 1.0;
    for (double sign : {-1.0, 1.0}) {
      if (std::isfinite(g.noise)) scatter.line(0, sign * g.noise, last, sign * g.noise, "noise");
      if (std::isfinite(g.threshold))
        scatter.line(0, sign * g.threshold, last, sign * g.threshold, "threshold");
    }
    for (int c = 0; c < rows; ++c) {
      const bool outlier = r.outlier[c];
      for (std::size_t k = 0; k < g.indices.size(); ++k) {
        const double v = residual(r, c, g.indices[k]) / g.scale[k];
        if (!std::isfinite(v)) continue;
        const std::string tip = "line " + count_text(r.lines[c]) + ", " +
                                r.reading_names[g.indices[k]] + ": " + fmt(v, 4) + " " + g.label +
                                (outlier ? " (outlier)" : "");
        scatter.point(c + 1.0, v, 2.6, "s" + std::to_string(k % 6), tip);
        if (outlier) scatter.point(c + 1.0, v, 5.5, "outlier-ring");
      }
    }
    // Legend: reading colours, then the lines.
    double lx = scatter.left() + 6;
    for (std::size_t k = 0; k < g.indices.size() && k < 12; ++k) {
      const std::string& name = r.reading_names[g.indices[k]];
      scatter.text_px(lx, scatter.top() + 12, "\xE2\x97\x8F " + name,
                      "legend s" + std::to_string(k % 6));
      lx += 12 + 7.0 * name.size();
    }
    scatter.text_px(scatter.right(), scatter.top() - 6,
                    "green dashed: \xC2\xB1sigma_hat; red dashed: outlier threshold", "legend",
                    "end");
    out += scatter.str();

    // Histogram against the noise.
    const int bins = std::clamp(static_cast<int>(std::sqrt(values.size())) * 2, 10, 40);
    const double width = 2 * extent / bins;
    std::vector<int> counts(bins, 0);
    for (double v : values)
      ++counts[std::clamp(static_cast<int>((v + extent) / width), 0, bins - 1)];
    const int top_count = *std::max_element(counts.begin(), counts.end());
    auto density = [&](double sigma, double x) {
      return values.size() * width * std::exp(-0.5 * x * x / (sigma * sigma)) /
             (sigma * std::sqrt(2 * kPi));
    };
    double ymax = top_count;
    if (std::isfinite(g.noise) && g.noise > 0) ymax = std::max(ymax, density(g.noise, 0));
    if (std::isfinite(g.stated) && g.stated > 0) ymax = std::max(ymax, density(g.stated, 0));
    SvgChart hist(1000, 260, "Histogram of the residuals against the noise");
    hist.set_x({-extent, extent, false, g.label});
    hist.set_y({0, ymax * 1.1, false, "readings"});
    hist.draw_axes();
    for (int b = 0; b < bins; ++b)
      hist.rect(-extent + b * width, 0, -extent + (b + 1) * width, counts[b], "bar",
                std::to_string(counts[b]) + " readings in [" + fmt(-extent + b * width, 3) + ", " +
                    fmt(-extent + (b + 1) * width, 3) + ")");
    auto curve = [&](double sigma, const std::string& css) {
      std::vector<std::pair<double, double>> pts;
      for (int i = 0; i <= 200; ++i) {
        const double x = -extent + 2 * extent * i / 200.0;
        pts.push_back({x, density(sigma, x)});
      }
      hist.polyline(pts, css);
    };
    std::string legend;
    if (std::isfinite(g.noise) && g.noise > 0) {
      curve(g.noise, "curve");
      legend += "green: normal with sigma_hat = " + fmt(g.noise, 3);
    }
    if (std::isfinite(g.stated) && g.stated > 0) {
      curve(g.stated, "curve2");
      legend += "; purple dashed: the stated reading_std";
    }
    hist.text_px(hist.right(), hist.top() - 6, legend, "legend", "end");
    out += hist.str();
  }
  return out;
}

struct ParameterRow {
  std::string name, unit;
  double nominal, estimate, change, std;
  bool weak;
};

std::vector<ParameterRow> parameter_rows(const CalibrationReport& r) {
  std::vector<ParameterRow> rows;
  std::set<std::string> weak_names;
  for (const auto& c : r.identifiability.combinations)
    for (const auto& term : c.terms) weak_names.insert(term.first);
  for (std::size_t i = 0; i < r.names.size(); ++i) {
    const int k = static_cast<int>(i);
    ParameterRow row{r.names[i],
                     r.units[i],
                     r.nominal[k],
                     r.estimate[k],
                     0,
                     r.uncertainty.std.size() ? finite_or_nan(r.uncertainty.std[k]) : NAN,
                     false};
    row.change = row.estimate - row.nominal;
    if (row.unit == "rad") row.change = std::remainder(row.change, 2 * kPi);
    row.weak = weak_names.count(row.name) > 0 || !(std::abs(row.change) >= row.std);
    rows.push_back(row);
  }
  return rows;
}

double correction_reach(const ParameterRow& p) {
  return std::abs(p.change) + (std::isfinite(p.std) ? p.std : 0);
}

struct CorrectionGroup {
  std::vector<const ParameterRow*> rows;
  std::string title_suffix;
};

// One unit's corrections, split where one scale would hide most of them: the corrections
// reaching beyond 10 times the group's 75th percentile (the UR5's 33.7 mm reflector offset
// beside 0.1 mm joint corrections) get a chart of their own, on their own scale.
std::vector<CorrectionGroup> correction_groups(const std::vector<const ParameterRow*>& all) {
  std::vector<double> reaches;
  for (const ParameterRow* p : all) reaches.push_back(correction_reach(*p));
  std::vector<double> sorted = reaches;
  std::sort(sorted.begin(), sorted.end());
  if (sorted.size() < 4) return {{all, ""}};  // too few to call one an exception
  const double typical = sorted[std::min(sorted.size() - 1, (sorted.size() * 3) / 4)];
  CorrectionGroup small, large;
  for (std::size_t i = 0; i < all.size(); ++i)
    (typical > 0 && reaches[i] > 10 * typical ? large : small).rows.push_back(all[i]);
  if (large.rows.empty() || small.rows.empty()) return {{all, ""}};
  large.title_suffix = large.rows.size() == 1 ? ", the large one on its own scale"
                                              : ", the " + std::to_string(large.rows.size()) +
                                                    " large ones on their own scale";
  small.title_suffix = ", the others";
  return {small, large};
}

std::string corrections_chart(const CorrectionGroup& group, const DisplayUnit& du) {
  const std::vector<const ParameterRow*>& list = group.rows;
  double extent = 0;
  std::size_t longest = 0;
  for (const auto* p : list) {
    extent = std::max(extent, correction_reach(*p) * du.scale);
    longest = std::max(longest, p->name.size());
  }
  extent = extent > 0 ? extent * 1.05 : 1;
  const int height = 30 + 46 + 18 * static_cast<int>(list.size());
  // Room for the longest name in the labels' 10 px monospace (0.6 em a character), so that
  // no label is clipped at the chart's left edge.
  const int margin = std::max(170, static_cast<int>(std::min<std::size_t>(longest, 80) * 6.2) + 16);
  SvgChart chart(1000, height, "Corrections (" + du.label + ")" + group.title_suffix, margin);
  chart.set_x({-extent, extent, false, "estimate - nominal (" + du.label + ")"});
  chart.set_y({0.5, static_cast<double>(list.size()) + 0.5, false, ""});
  chart.draw_axes(true, false);
  chart.line(0, 0.5, 0, list.size() + 0.5, "zero");
  for (std::size_t i = 0; i < list.size(); ++i) {
    const ParameterRow& p = *list[i];
    // First parameter at the top.
    const double y = static_cast<double>(list.size() - i), c = p.change * du.scale,
                 s = p.std * du.scale;
    chart.text_px(chart.left() - 4, chart.py(y) + 4, p.name, "label", "end");
    if (std::isfinite(s)) {
      chart.line(c - s, y, c + s, y, "errbar");
      chart.line(c - s, y - 0.25, c - s, y + 0.25, "errbar");
      chart.line(c + s, y - 0.25, c + s, y + 0.25, "errbar");
    }
    chart.point(c, y, 3.5, p.weak ? "est-weak" : "est",
                p.name + ": " + fmt(c, 4) + " \xC2\xB1 " + fmt(s, 3) + " " + du.label);
  }
  return chart.str();
}

std::string parameters_html(const CalibrationReport& r) {
  const std::vector<ParameterRow> rows = parameter_rows(r);
  if (rows.empty()) return "<p>No estimated parameters.</p>";
  std::string out =
      "<p>Correction = estimate - nominal, with an error bar of \xC2\xB1 one standard deviation. "
      "Orange: a correction within its own std, or a parameter in a weakly determined "
      "direction (section Identifiability).</p>";
  std::map<std::string, std::vector<const ParameterRow*>> by_unit;
  for (const auto& row : rows) by_unit[row.unit].push_back(&row);
  for (const auto& [unit, all] : by_unit) {
    for (const CorrectionGroup& group : correction_groups(all))
      out += corrections_chart(group, display_unit(unit));
  }
  // The table, with the prior's columns.
  const ParameterUncertainty& u = r.uncertainty;
  out +=
      "<table><tr><th class=\"name\">parameter</th><th>unit</th><th>nominal</th>"
      "<th>estimate</th><th>correction</th><th>std</th><th>prior std</th><th>data share</th>"
      "</tr>";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const int k = static_cast<int>(i);
    const ParameterRow& p = rows[i];
    const DisplayUnit du = display_unit(p.unit);
    const double prior_std = u.prior_std.size() && u.prior_std[k] > 0 ? u.prior_std[k] : NAN;
    const double share =
        u.std.size() ? (u.data_share.size() ? finite_or_nan(u.data_share[k]) : 1.0) : NAN;
    out += std::string("<tr") + (p.weak ? " class=\"weak\"" : "") + "><td class=\"name\">" +
           esc(p.name) + "</td><td>" + esc(du.label) + "</td><td>" + fmt(p.nominal * du.scale, 8) +
           "</td><td>" + fmt(p.estimate * du.scale, 8) + "</td><td>" + fmt(p.change * du.scale, 4) +
           "</td><td>" + fmt(p.std * du.scale, 3) + "</td><td>" + fmt(prior_std * du.scale, 3) +
           "</td><td>" + fmt(share, 3) + "</td></tr>";
  }
  out += "</table>";
  if (!r.fixed_by_identifiability.empty()) {
    out += "<p>Fixed at their model values because the data cannot determine them (" +
           std::to_string(r.fixed_by_identifiability.size()) +
           "), each with what it duplicates, a direction the data cannot see:</p>"
           "<table><tr><th class=\"name\">parameter</th><th class=\"name\">in words</th>"
           "<th class=\"name\">what the data see of it</th></tr>";
    for (std::size_t i = 0; i < r.fixed_by_identifiability.size(); ++i) {
      const std::string& name = r.fixed_by_identifiability[i];
      out += "<tr><td class=\"name\">" + esc(name) + "</td><td class=\"name\">" +
             esc(parameter_words(name)) + "</td><td class=\"name\">" +
             esc(i < r.fixed_effects.size() ? r.fixed_effects[i] : std::string("not determined")) +
             "</td></tr>";
    }
    out += "</table>";
  }
  return out;
}

std::string correlation_html(const CalibrationReport& r) {
  const MatrixXd& corr = r.uncertainty.correlation;
  if (corr.rows() == 0)
    return "<p>No correlation matrix (the standard deviations could not be computed).</p>";
  const std::size_t n = std::min(static_cast<std::size_t>(corr.rows()), r.names.size());
  const double cell = std::clamp(600.0 / n, 5.0, 22.0);
  const int left = 190, top = 40;
  const int width = left + static_cast<int>(cell * n) + 140;
  const int height = top + static_cast<int>(cell * n) + 30;
  SvgChart chart(width, height, "Correlation of the estimates", left);
  chart.text_px(left, 18, "Correlation of the estimates (blue -1, white 0, red +1)", "chart-title");
  for (std::size_t i = 0; i < n; ++i) {
    const std::string& name_i = r.names[i];
    if (cell >= 8)
      chart.text_px(left - 4, top + (i + 0.75) * cell, std::to_string(i + 1) + " " + name_i,
                    "label", "end");
    for (std::size_t j = 0; j < n && j < static_cast<std::size_t>(corr.cols()); ++j) {
      const double c = finite_or_nan(corr(static_cast<int>(i), static_cast<int>(j)));
      chart.cell_px(left + j * cell, top + i * cell, cell, cell, diverging_colour(c),
                    name_i + " / " + r.names[j] + ": " + fmt(c, 4));
    }
  }
  if (cell >= 8)
    for (std::size_t j = 0; j < n; j += (n > 30 ? 5 : 1))
      chart.text_px(left + (j + 0.5) * cell, top - 4, std::to_string(j + 1), "tick", "middle");
  // Colour scale.
  const double sx = left + cell * n + 30;
  for (int k = 0; k < 20; ++k)
    chart.cell_px(sx, top + k * 10.0, 16, 10, diverging_colour(1 - (k + 0.5) / 10.0));
  chart.text_px(sx + 20, top + 8, "+1", "tick");
  chart.text_px(sx + 20, top + 104, "0", "tick");
  chart.text_px(sx + 20, top + 200, "-1", "tick");
  std::string out = chart.str();
  out +=
      "<p>Each cell is the correlation of two estimates (hover for the names and value). "
      "\xC2\xB1"
      "1 means the data determine only a combination of the two.</p>";
  return out;
}

std::string outliers_html(const CalibrationReport& r) {
  std::string table;
  int count = 0;
  for (int c = 0; c < r.residuals.rows(); ++c) {
    if (!r.outlier[c]) continue;
    ++count;
    table += "<tr class=\"outlier\"><td>" + esc(count_text(r.lines[c])) + "</td>";
    for (std::size_t k = 0; k < r.reading_names.size(); ++k)
      table += "<td>" + esc(fmt(residual(r, c, k), 4)) + "</td>";
    table += "</tr>";
  }
  if (!count)
    return "<p>No configuration is flagged: every residual is within the threshold (" +
           esc(fmt(r.outlier_threshold, 3)) + "). " + esc(outlier_meaning(r)) + ".</p>";
  std::string out = "<p>" + esc(outlier_meaning(r)) + ".</p><p>" + std::to_string(count) +
                    " configuration(s) have a residual beyond the threshold (" +
                    esc(fmt(r.outlier_threshold, 3)) + (r.weighted ? " x reading_std" : "") +
                    "):</p><table><tr><th>line</th>";
  for (const auto& name : r.reading_names) out += "<th>" + esc(name) + "</th>";
  return out + "</tr>" + table + "</table>";
}

std::string constraints_html(const CalibrationReport& r) {
  if (r.constraints.empty()) return {};
  std::string out =
      "<p>Known relations between parameters, fitted with the data; a residual of a few stds "
      "says the data and the stated value disagree.</p><table><tr><th>constraint</th>"
      "<th>type</th><th>residual</th><th>std</th><th>residual / std</th></tr>";
  for (const auto& c : r.constraints) {
    const std::string unit = " " + c.unit;
    const double res = finite_or_nan(c.residual), std = c.std;
    out += "<tr><td class=\"name\">" + esc(c.label) + "</td><td class=\"name\">" + esc(c.type) +
           "</td><td>" + esc(fmt(res, 4) + unit) + "</td><td>" + esc(fmt(std, 4) + unit) +
           "</td><td>" + esc(fmt(res / std, 3)) + "</td></tr>";
  }
  return out + "</table>";
}

std::string summary_html(const CalibrationReport& r, const CalibrationPageExtras& extras) {
  std::string out = "<table>";
  out += summary_row("model", r.model_file);
  out += summary_row("data", r.data_file);
  out += summary_row("solver",
                     r.summary.solver + ", loss " + r.loss +
                         (r.formulation.empty() ? "" : ", " + r.formulation + " formulation"));
  // Why the formulation asked for is not the one solved (an implicit solve that failed).
  if (!r.formulation_note.empty()) out += summary_row("formulation", r.formulation_note);
  out += summary_row("outcome", std::string(to_string(r.summary.termination)) + " after " +
                                    count_text(r.summary.iterations) +
                                    " iterations: " + r.summary.message);
  out += summary_row("configurations", count_text(r.num_configurations) + " (" +
                                           count_text(r.num_readings) + " readings)");
  for (const auto& [unit, rms] : r.residual_rms) {
    const auto max = r.residual_max.find(unit);
    out += summary_row(
        "residuals (" + unit + ")",
        "RMS " + fmt(rms, 4) + ", max " + fmt(max != r.residual_max.end() ? max->second : NAN, 4));
  }
  out += summary_row("sigma_hat", fmt(finite_or_nan(r.uncertainty.sigma), 4) + " " + sigma_unit(r) +
                                      " (" + count_text(r.uncertainty.degrees_of_freedom) +
                                      " degrees of freedom)");
  if (!extras.calibrated_model_file.empty())
    out += summary_row("calibrated model", extras.calibrated_model_file + " (sha256 " +
                                               extras.calibrated_model_sha256 + ")");
  return out + "</table>";
}

// The measured 3-D position error of the measured point (a point tracker's): before
// calibration, registration only, calibrated, in-sample and held out (--folds), as a table
// and a bar chart of the mean and max, and the error the parameters' uncertainty predicts at
// the measured configurations.
std::string measured_position_error_html(const CalibrationReport& r) {
  struct Row {
    std::string model, data;
    const PositionErrorStats* stats;
  };
  std::vector<Row> rows;
  const std::string in_sample = "calibration data (in-sample)";
  rows.push_back({"before calibration (starting values)", in_sample, &r.position_before});
  if (r.registration.computed)
    rows.push_back({"registration only (frames fitted)", in_sample, &r.registration.position});
  rows.push_back({"calibrated", in_sample, &r.position_after});
  const auto& cv = r.cross_validation;
  const std::string held_out = "held out, " + fmt(cv.folds, 3) + "-fold cross-validation";
  if (cv.folds > 0 && cv.position.points > 0) {
    rows.push_back({"registration only (frames fitted)", held_out, &cv.registration_position});
    rows.push_back({"calibrated", held_out, &cv.position});
  }
  std::string out =
      "<table><tr><th class=\"name\">model</th><th class=\"name\">data</th><th>points</th>"
      "<th>mean (mm)</th><th>RMS (mm)</th><th>max (mm)</th></tr>";
  double top = 0;
  for (const Row& row : rows) {
    const double mean = finite_or_nan(row.stats->mean), rms = finite_or_nan(row.stats->rms),
                 max = finite_or_nan(row.stats->max);
    out += "<tr><td class=\"name\">" + esc(row.model) + "</td><td class=\"name\">" + esc(row.data) +
           "</td><td>" + fmt(row.stats->points, 9) + "</td><td>" + fmt(mean) + "</td><td>" +
           fmt(rms) + "</td><td>" + fmt(max) + "</td></tr>";
    for (double v : {mean, max})
      if (std::isfinite(v)) top = std::max(top, v);
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
    const double y = n - i, mean = finite_or_nan(row.stats->mean),
                 max = finite_or_nan(row.stats->max);
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
  const PointErrorPrediction& p = r.predicted_point;
  out += "<p>Predicted from the parameters' uncertainty at the " + fmt(p.points, 9) +
         " measured configurations: 1 sigma mean " + fmt(finite_or_nan(p.mean_1sigma)) +
         " mm, worst " + fmt(finite_or_nan(p.max_1sigma)) + " mm; 95 % quantile mean " +
         fmt(finite_or_nan(p.mean_95)) + " mm, worst " + fmt(finite_or_nan(p.max_95)) +
         " mm (RMS " + fmt(finite_or_nan(p.rms)) + " mm).</p>";
  return out;
}

std::string pose_accuracy_section(const CalibrationReport& r, const CalibrationPageExtras& extras) {
  const AccuracyComparison& a = r.predicted_accuracy;
  std::string out = a.computed
                        ? pose_accuracy_html(a.calibrated.samples,
                                             {{"calibrated", &a.calibrated},
                                              {"nominal model (assumed spread)", &a.nominal}},
                                             extras.target ? &*extras.target : nullptr)
                        : "<p>Not computed: " + esc(a.why_not) + ".</p>";
  if (!r.pose_accuracy_shown) out += "<p class=\"note\">" + esc(kPoseAccuracyNotShown) + ".</p>";
  return out;
}

}  // namespace

std::string calibration_html(const CalibrateResult& result, const CalibrationPageExtras& extras) {
  const CalibrationReport& r = result.report;
  HtmlPage page("kincal calibration report: " + r.model_file + " from " + r.data_file);
  const std::vector<Finding> findings = calibration_page_findings(result, extras);
  std::string next;
  for (const auto& f : findings)
    if (!f.advice.empty()) next += "<li>" + esc(f.advice) + "</li>";
  page.add_section(
      "verdicts", "Verdicts",
      findings_html(findings) + (next.empty() ? "<p>Nothing to do: load the calibrated model.</p>"
                                              : "<h3>What to do next</h3><ol>" + next + "</ol>"));
  page.add_section("summary", "Summary", summary_html(r, extras));
  page.add_section("residuals", "Residuals", residuals_html(r));
  page.add_section("parameters", "Parameter corrections", parameters_html(r));
  const std::string constraints = constraints_html(r);
  if (!constraints.empty()) page.add_section("constraints", "Constraints", constraints);
  page.add_section("correlation", "Correlations", correlation_html(r));
  page.add_section("identifiability", "Identifiability", identifiability_html(r.identifiability));
  page.add_section("outliers", "Outliers", outliers_html(r));
  if (r.position_after.points > 0)
    page.add_section("position-error", "3-D position error of the measured point",
                     measured_position_error_html(r));
  if (!extras.image_views.empty()) {
    std::string html;
    for (const ImageViews& views : extras.image_views) html += image_views_html(views);
    page.add_section("camera-views", "Camera views", html);
  }
  page.add_section("pose-accuracy", "Predicted pose accuracy", pose_accuracy_section(r, extras));
  if (extras.sensitivity)
    page.add_section("sensitivity", "Sensitivity to fixed parameters",
                     sensitivity_html(*extras.sensitivity,
                                      extras.target ? extras.target->target.position_mm : NAN));
  if (!r.warnings.empty()) {
    std::string list = "<ul>";
    for (const auto& w : r.warnings) list += "<li>" + esc(w) + "</li>";
    page.add_section("warnings", "Warnings", list + "</ul>");
  }
  return page.str();
}

}  // namespace kincal::report
