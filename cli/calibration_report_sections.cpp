// The sections of the calibration report's page (cli/calibration_report_sections.hpp).

#include "kincal/cli/calibration_report_sections.hpp"
#include "kincal/framework/analysis/identifiability.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "kincal/cli/html_values.hpp"

namespace kincal::cli {

using namespace html_values;

namespace {

// Residual groups: one chart per unit, or one in multiples of the stated std when weighted.
struct ResidualGroup {
  std::string label;                  // axis unit
  std::vector<std::string> readings;  // reading names
  std::vector<double> scale;          // divide residuals by this
  double noise = NAN;                 // the +-band: sigma_hat in the group's unit
  double stated = NAN;                // the stated noise (weighted: 1)
  double threshold = NAN;             // outlier threshold in the group's unit
};

std::vector<ResidualGroup> residual_groups(const Json& r) {
  std::vector<ResidualGroup> groups;
  const Json& units = member(r, "reading_units");
  const Json& stds = member(r, "reading_std");
  const bool weighted = member(r, "weighted").is_boolean() && r["weighted"].get<bool>();
  const double sigma = num(member(r, "sigma_hat"));
  const std::string sigma_unit = text_of(r, "sigma_hat_unit");
  const double threshold = num(member(r, "outlier_threshold"));
  if (!units.is_object()) return groups;
  if (weighted) {
    ResidualGroup g{"residual / reading_std", {}, {}, sigma, 1.0, threshold};
    for (const auto& [name, unit] : units.items()) {
      g.readings.push_back(name);
      const double s = num(member(stds, name.c_str()));
      g.scale.push_back(std::isfinite(s) && s > 0 ? s : 1.0);
    }
    groups.push_back(g);
    return groups;
  }
  std::map<std::string, std::size_t> index;
  for (const auto& [name, unit_json] : units.items()) {
    const std::string unit = text_of(unit_json);
    if (!index.count(unit)) {
      index[unit] = groups.size();
      const DisplayUnit du = display_unit(unit);
      groups.push_back({du.label,
                        {},
                        {},
                        sigma_unit == unit ? sigma * du.scale : NAN,
                        NAN,
                        // Each unit has its own threshold (outlier_threshold_by_unit).
                        (member(member(r, "outlier_threshold_by_unit"), unit.c_str()).is_number()
                             ? num(r["outlier_threshold_by_unit"][unit])
                             : threshold) *
                            du.scale});
    }
    groups[index[unit]].readings.push_back(name);
    groups[index[unit]].scale.push_back(1.0 / display_unit(unit).scale);
  }
  return groups;
}

}  // namespace

std::string calibration_residuals_html(const Json& r) {
  const Json& rows = member(r, "residuals");
  if (!rows.is_array() || rows.empty()) return "<p>No residuals (they could not be computed).</p>";
  std::string out;
  for (const ResidualGroup& g : residual_groups(r)) {
    std::vector<double> values;
    double extent = 0;
    for (const auto& row : rows)
      for (std::size_t k = 0; k < g.readings.size(); ++k) {
        const double v = num(member(row, g.readings[k].c_str())) / g.scale[k];
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
    scatter.set_x(
        {0, static_cast<double>(rows.size() + 1), false, "configuration (in file order)"});
    scatter.set_y({-extent, extent, false, g.label});
    scatter.draw_axes();
    scatter.line(0, 0, rows.size() + 1.0, 0, "zero");
    const double last = rows.size() + 1.0;
    for (double sign : {-1.0, 1.0}) {
      if (std::isfinite(g.noise)) scatter.line(0, sign * g.noise, last, sign * g.noise, "noise");
      if (std::isfinite(g.threshold))
        scatter.line(0, sign * g.threshold, last, sign * g.threshold, "threshold");
    }
    for (std::size_t c = 0; c < rows.size(); ++c) {
      const bool outlier =
          member(rows[c], "outlier").is_boolean() && rows[c]["outlier"].get<bool>();
      for (std::size_t k = 0; k < g.readings.size(); ++k) {
        const double v = num(member(rows[c], g.readings[k].c_str())) / g.scale[k];
        if (!std::isfinite(v)) continue;
        const std::string tip = "line " + text_of(rows[c], "line") + ", " + g.readings[k] + ": " +
                                fmt(v, 4) + " " + g.label + (outlier ? " (outlier)" : "");
        scatter.point(c + 1.0, v, 2.6, "s" + std::to_string(k % 6), tip);
        if (outlier) scatter.point(c + 1.0, v, 5.5, "outlier-ring");
      }
    }
    // Legend: reading colours, then the lines.
    double lx = scatter.left() + 6;
    for (std::size_t k = 0; k < g.readings.size() && k < 12; ++k) {
      scatter.text_px(lx, scatter.top() + 12, "\xE2\x97\x8F " + g.readings[k],
                      "legend s" + std::to_string(k % 6));
      lx += 12 + 7.0 * g.readings[k].size();
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

namespace {

struct ParameterRow {
  std::string name, unit;
  double nominal, estimate, change, std;
  bool weak;
};

std::vector<ParameterRow> parameter_rows(const Json& r) {
  std::vector<ParameterRow> rows;
  std::set<std::string> weak_names;
  for (const auto& c : member(member(r, "identifiability"), "combinations"))
    for (const auto& t : member(c, "terms")) weak_names.insert(text_of(t, "name"));
  for (const auto& p : member(r, "parameters")) {
    ParameterRow row{text_of(p, "name"),
                     text_of(p, "unit"),
                     num(member(p, "nominal")),
                     num(member(p, "estimate")),
                     0,
                     num(member(p, "std")),
                     false};
    row.change = row.estimate - row.nominal;
    if (row.unit == "rad") row.change = std::remainder(row.change, 2 * kPi);
    row.weak = weak_names.count(row.name) > 0 || !(std::abs(row.change) >= row.std);
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

std::string calibration_parameters_html(const Json& r) {
  const std::vector<ParameterRow> rows = parameter_rows(r);
  if (rows.empty()) return "<p>No estimated parameters.</p>";
  std::string out =
      "<p>Correction = estimate - nominal, with an error bar of \xC2\xB1 one standard deviation. "
      "Orange: a correction within its own std, or a parameter in a weakly determined "
      "direction (section Identifiability).</p>";
  std::map<std::string, std::vector<const ParameterRow*>> by_unit;
  for (const auto& row : rows) by_unit[row.unit].push_back(&row);
  for (const auto& [unit, list] : by_unit) {
    const DisplayUnit du = display_unit(unit);
    double extent = 0;
    for (const auto* p : list) {
      const double reach = std::abs(p->change) + (std::isfinite(p->std) ? p->std : 0);
      extent = std::max(extent, reach * du.scale);
    }
    extent = extent > 0 ? extent * 1.05 : 1;
    const int height = 30 + 46 + 18 * static_cast<int>(list.size());
    SvgChart chart(1000, height, "Corrections (" + du.label + ")", 170);
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
    out += chart.str();
  }
  // The table, with optional prior columns.
  bool has_prior = false, has_share = false;
  for (const auto& p : member(r, "parameters")) {
    has_prior = has_prior || p.contains("prior_std");
    has_share = has_share || p.contains("data_share");
  }
  out +=
      "<table><tr><th class=\"name\">parameter</th><th>unit</th><th>nominal</th>"
      "<th>estimate</th><th>correction</th><th>std</th>";
  if (has_prior) out += "<th>prior std</th>";
  if (has_share) out += "<th>data share</th>";
  out += "</tr>";
  const Json& params = member(r, "parameters");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const ParameterRow& p = rows[i];
    const DisplayUnit du = display_unit(p.unit);
    out += std::string("<tr") + (p.weak ? " class=\"weak\"" : "") + "><td class=\"name\">" +
           esc(p.name) + "</td><td>" + esc(du.label) + "</td><td>" + fmt(p.nominal * du.scale, 8) +
           "</td><td>" + fmt(p.estimate * du.scale, 8) + "</td><td>" + fmt(p.change * du.scale, 4) +
           "</td><td>" + fmt(p.std * du.scale, 3) + "</td>";
    if (has_prior) out += "<td>" + fmt(num(member(params[i], "prior_std")) * du.scale, 3) + "</td>";
    if (has_share) out += "<td>" + fmt(num(member(params[i], "data_share")), 3) + "</td>";
    out += "</tr>";
  }
  out += "</table>";
  if (member(r, "fixed_by_identifiability").is_array() && !r["fixed_by_identifiability"].empty()) {
    out += "<p>Fixed at their model values because the data cannot determine them:";
    for (const auto& name : r["fixed_by_identifiability"])
      out += " <code>" + esc(text_of(name)) + "</code>";
    out += "</p>";
  }
  return out;
}

std::string calibration_correlation_html(const Json& r) {
  const Json& corr = member(r, "correlation");
  const Json& params = member(r, "parameters");
  if (!corr.is_array() || corr.empty() || !params.is_array())
    return "<p>No correlation matrix (the standard deviations could not be computed).</p>";
  const std::size_t n = std::min(corr.size(), params.size());
  const double cell = std::clamp(600.0 / n, 5.0, 22.0);
  const int left = 190, top = 40;
  const int width = left + static_cast<int>(cell * n) + 140;
  const int height = top + static_cast<int>(cell * n) + 30;
  SvgChart chart(width, height, "Correlation of the estimates", left);
  chart.text_px(left, 18, "Correlation of the estimates (blue -1, white 0, red +1)", "chart-title");
  for (std::size_t i = 0; i < n; ++i) {
    const std::string name_i = text_of(params[i], "name");
    if (cell >= 8)
      chart.text_px(left - 4, top + (i + 0.75) * cell, std::to_string(i + 1) + " " + name_i,
                    "label", "end");
    for (std::size_t j = 0; j < n && j < corr[i].size(); ++j) {
      const double c = num(corr[i][j]);
      chart.cell_px(left + j * cell, top + i * cell, cell, cell, diverging_colour(c),
                    name_i + " / " + text_of(params[j], "name") + ": " + fmt(c, 4));
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

std::string identifiability_html(const Json& r) {
  const Json& id = member(r, "identifiability");
  const Json& sv = member(id, "singular_values");
  if (!sv.is_array() || sv.empty()) return "<p>No identifiability analysis.</p>";
  std::vector<double> s;
  for (const auto& v : sv) s.push_back(num(v));
  const double threshold = num(member(id, "numerical_rank_threshold"));
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
  const double weak = 1e-4 * s1;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double v = s[i] > 0 ? s[i] : lo;
    const char* css = s[i] < threshold ? "sv-null" : s[i] < weak ? "sv-weak" : "sv";
    chart.point(i + 1.0, v, 3.5, css, "s" + std::to_string(i + 1) + " = " + fmt(s[i], 4));
  }
  std::string out = chart.str();
  const double cond = num(member(id, "condition_number"));
  const int n = member(id, "parameters").is_number() ? id["parameters"].get<int>() : 0;
  const int rank = member(id, "numerical_rank").is_number() ? id["numerical_rank"].get<int>() : 0;
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
  out += " O1 " + esc(fmt(num(member(id, "O1")), 3)) + ", O2 " +
         esc(fmt(num(member(id, "O2")), 3)) + ", O3 " + esc(fmt(num(member(id, "O3")), 3)) +
         ", O4 " + esc(fmt(num(member(id, "O4")), 3)) + ", O5 " +
         esc(fmt(num(member(id, "O5")), 3)) + " (larger is better).</p>";
  const Json& combos = member(id, "combinations");
  if (combos.is_array() && !combos.empty()) {
    out +=
        "<p>Weakest directions (moving the parameters along one changes the readings by "
        "almost nothing):</p><table><tr><th>kind</th><th>singular value</th>"
        "<th class=\"name\">combination</th></tr>";
    int shown = 0;
    for (const auto& c : combos) {
      if (shown++ == 8) break;
      std::string terms;
      for (const auto& t : member(c, "terms")) {
        const double k = num(member(t, "coefficient"));
        terms += (k >= 0 ? " +" : " ") + fmt(k, 3) + " " + text_of(t, "name");
      }
      out +=
          "<tr><td>" +
          esc(text_of(c, "kind") == "null_space" ? "cannot be determined" : "weakly determined") +
          "</td><td>" + esc(fmt(num(member(c, "singular_value")), 3)) + "</td><td class=\"name\">" +
          esc(terms) + "</td></tr>";
    }
    out += "</table>";
  }
  return out;
}

std::string calibration_outliers_html(const Json& r) {
  const Json& rows = member(r, "residuals");
  std::vector<std::string> names;
  if (member(r, "reading_units").is_object())
    for (const auto& [name, unit] : r["reading_units"].items()) names.push_back(name);
  std::string table;
  int count = 0;
  for (const auto& row : rows) {
    if (!(member(row, "outlier").is_boolean() && row["outlier"].get<bool>())) continue;
    ++count;
    table += "<tr class=\"outlier\"><td>" + esc(text_of(row, "line")) + "</td>";
    for (const auto& name : names)
      table += "<td>" + esc(fmt(num(member(row, name.c_str())), 4)) + "</td>";
    table += "</tr>";
  }
  if (!count)
    return "<p>No configuration is flagged: every residual is within the threshold (" +
           esc(fmt(num(member(r, "outlier_threshold")), 3)) + "). " +
           esc(text_of(r, "outlier_meaning")) + ".</p>";
  std::string out =
      "<p>" + esc(text_of(r, "outlier_meaning")) + ".</p><p>" + std::to_string(count) +
      " configuration(s) have a residual beyond the threshold (" +
      esc(fmt(num(member(r, "outlier_threshold")), 3)) +
      (member(r, "weighted").is_boolean() && r["weighted"].get<bool>() ? " x reading_std" : "") +
      "):</p><table><tr><th>line</th>";
  for (const auto& name : names) out += "<th>" + esc(name) + "</th>";
  return out + "</tr>" + table + "</table>";
}

std::string calibration_constraints_html(const Json& r) {
  const Json& constraints = member(r, "constraints");
  if (!constraints.is_array() || constraints.empty()) return {};
  std::string out =
      "<p>Known relations between parameters, fitted with the data; a residual of a few stds "
      "says the data and the stated value disagree.</p><table><tr><th>constraint</th>"
      "<th>type</th><th>residual</th><th>std</th><th>residual / std</th></tr>";
  for (const auto& c : constraints) {
    const std::string unit = " " + text_of(c, "unit");
    const double residual = num(member(c, "residual")), std = num(member(c, "std"));
    out += "<tr><td class=\"name\">" + esc(text_of(c, "label")) + "</td><td class=\"name\">" +
           esc(text_of(c, "type")) + "</td><td>" + esc(fmt(residual, 4) + unit) + "</td><td>" +
           esc(fmt(std, 4) + unit) + "</td><td>" + esc(fmt(residual / std, 3)) + "</td></tr>";
  }
  return out + "</table>";
}

std::string calibration_summary_html(const Json& r) {
  std::string out = "<table>";
  auto row = [&](const std::string& key, const std::string& value) {
    out += "<tr><th class=\"name\">" + esc(key) + "</th><td class=\"name\">" + esc(value) +
           "</td></tr>";
  };
  row("model", text_of(r, "model"));
  row("data", text_of(r, "data"));
  const std::string formulation = text_of(r, "formulation");
  row("solver", text_of(r, "solver") + ", loss " + text_of(r, "loss") +
                    (formulation.empty() ? "" : ", " + formulation + " formulation"));
  // Why the formulation asked for is not the one solved (an implicit solve that failed).
  const std::string formulation_note = text_of(r, "formulation_note");
  if (!formulation_note.empty()) row("formulation", formulation_note);
  row("outcome", text_of(r, "termination") + " after " + text_of(r, "iterations") +
                     " iterations: " + text_of(r, "message"));
  row("configurations",
      text_of(r, "configurations") + " (" + text_of(r, "readings") + " readings)");
  if (member(r, "residual_rms_by_unit").is_object())
    for (const auto& [unit, rms] : r["residual_rms_by_unit"].items())
      row("residuals (" + unit + ")",
          "RMS " + fmt(num(rms), 4) + ", max " +
              fmt(num(member(r["residual_max_by_unit"], unit.c_str())), 4));
  row("sigma_hat", fmt(num(member(r, "sigma_hat")), 4) + " " + text_of(r, "sigma_hat_unit") + " (" +
                       text_of(r, "degrees_of_freedom") + " degrees of freedom)");
  const Json& cm = member(r, "calibrated_model");
  if (cm.is_object())
    row("calibrated model", text_of(cm, "file") + " (sha256 " + text_of(cm, "sha256") + ")");
  return out + "</table>";
}

}  // namespace kincal::cli
