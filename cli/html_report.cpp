#include "kincal/cli/html_report.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "kincal/cli/html_pose_accuracy.hpp"
#include "kincal/cli/html_sensitivity.hpp"
#include "kincal/cli/svg_plot.hpp"

namespace kincal::cli {

namespace {

using Json = nlohmann::ordered_json;
constexpr double kPi = 3.14159265358979323846;

double num(const Json& j) { return j.is_number() ? j.get<double>() : NAN; }
std::string text_of(const Json& j) {
  return j.is_string() ? j.get<std::string>() : j.is_null() ? "" : plain_text(j);
}
std::string text_of(const Json& j, const char* key) {
  return j.is_object() && j.contains(key) ? text_of(j[key]) : "";
}
const Json& member(const Json& j, const char* key) {
  static const Json null_value;
  return j.is_object() && j.contains(key) ? j[key] : null_value;
}

std::string esc(const std::string& s) { return xml_escape(s); }
std::string fmt(double v, int digits = 4) { return format_number(v, digits); }

// Angles are stored in rad and shown in mrad: corrections of a few mrad read better.
struct DisplayUnit {
  std::string label;
  double scale = 1;
};
DisplayUnit display_unit(const std::string& unit) {
  if (unit == "rad") return {"mrad", 1000};
  return {unit, 1};
}

const char* level_class(Verdict::Level level) {
  switch (level) {
    case Verdict::Level::kGood:
      return "good";
    case Verdict::Level::kNote:
      return "note";
    case Verdict::Level::kWarning:
      return "warning";
    case Verdict::Level::kProblem:
      return "problem";
  }
  return "note";
}

const char* level_word(Verdict::Level level) {
  switch (level) {
    case Verdict::Level::kGood:
      return "OK";
    case Verdict::Level::kNote:
      return "Note";
    case Verdict::Level::kWarning:
      return "Warning";
    case Verdict::Level::kProblem:
      return "Problem";
  }
  return "";
}

const char* kStyle = R"(
body{font-family:sans-serif;margin:24px auto;padding:0 16px;max-width:1100px;color:#222;line-height:1.4}
h1{font-size:1.5em;margin-bottom:.2em} h2{font-size:1.2em;border-bottom:1px solid #ccc;margin-top:1.6em}
table{border-collapse:collapse;font-size:.9em;margin:.5em 0} td,th{border:1px solid #ddd;padding:2px 8px;text-align:right}
th{background:#f4f4f4} td.name,th.name{text-align:left;font-family:monospace}
nav a{margin-right:1em} .small{font-size:.85em;color:#555}
ul.verdicts{list-style:none;padding-left:0} ul.verdicts li{margin:.4em 0;padding:.4em .6em;border-left:5px solid #999;background:#fafafa}
li.good{border-color:#2e8b57!important} li.note{border-color:#4a78b0!important}
li.warning{border-color:#e0a100!important} li.problem{border-color:#c0392b!important}
.level{font-weight:bold;margin-right:.4em} .action{display:block;color:#333;font-style:italic}
tr.weak td{background:#fff4e0} tr.outlier td{background:#fde8e6}
svg{display:block;margin:.6em 0;background:#fff}
svg .frame{fill:none;stroke:#888} svg .grid{stroke:#eee} svg .tick{font-size:10px;fill:#555}
svg .axis-label{font-size:11px;fill:#333} svg .chart-title{font-size:12px;font-weight:bold;fill:#222}
svg .zero{stroke:#444;stroke-width:1} svg .noise{stroke:#2e8b57;stroke-dasharray:4 3;stroke-width:1.2}
svg .threshold{stroke:#c0392b;stroke-dasharray:6 3;stroke-width:1.2}
svg .bar{fill:#7a9cc6;stroke:#fff} svg .curve{fill:none;stroke:#2e8b57;stroke-width:2}
svg .curve2{fill:none;stroke:#8e44ad;stroke-width:2;stroke-dasharray:5 3}
svg .errbar{stroke:#333;stroke-width:1.3} svg .est{fill:#1f5fa8} svg .est-weak{fill:#e0a100}
svg .sv{fill:#1f5fa8} svg .sv-weak{fill:#e0a100} svg .sv-null{fill:#c0392b}
svg .outlier-ring{fill:none;stroke:#c0392b;stroke-width:1.5} svg .legend{font-size:10px;fill:#333}
svg .s0{fill:#1f5fa8} svg .s1{fill:#2e8b57} svg .s2{fill:#8e44ad} svg .s3{fill:#d35400} svg .s4{fill:#16a085} svg .s5{fill:#7f8c8d}
svg .label{font-size:10px;fill:#222;font-family:monospace}
)";

}  // namespace

// ---------------------------------------------------------------------------------------
// Page

HtmlPage::HtmlPage(std::string title) : title_(std::move(title)) {}

void HtmlPage::add_section(const std::string& id, const std::string& heading,
                           const std::string& html) {
  toc_.push_back("<a href=\"#" + esc(id) + "\">" + esc(heading) + "</a>");
  sections_.push_back("<section id=\"" + esc(id) + "\"><h2>" + esc(heading) + "</h2>" + html +
                      "</section>\n");
}

std::string HtmlPage::str() const {
  std::string out =
      "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"/>"
      "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; style-src "
      "'unsafe-inline'; img-src data:\"/>"
      "<title>" +
      esc(title_) + "</title><style>" + kStyle + "</style></head>\n<body><h1>" + esc(title_) +
      "</h1>\n<nav>";
  for (const auto& link : toc_) out += link;
  out += "</nav>\n";
  for (const auto& s : sections_) out += s;
  out +=
      "<p class=\"small\">Written by kincal. This file needs no network and no script.</p>"
      "</body></html>\n";
  return out;
}

std::string verdicts_html(const std::vector<Verdict>& verdicts) {
  std::string out = "<ul class=\"verdicts\">";
  for (const auto& v : verdicts) {
    out += "<li class=\"" + std::string(level_class(v.level)) + "\"><span class=\"level\">" +
           level_word(v.level) + "</span>" + esc(v.finding);
    if (!v.action.empty())
      out += "<span class=\"action\">\xE2\x86\x92 " + esc(v.action) + "</span>";
    out += "</li>";
  }
  return out + "</ul>";
}

std::string plain_text(const Json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number()) return fmt(v.get<double>(), 5);
  if (v.is_boolean()) return v.get<bool>() ? "yes" : "no";
  if (v.is_null()) return "\xE2\x80\x93";  // en dash: none
  std::string out;
  if (v.is_array()) {
    for (const auto& item : v) out += (out.empty() ? "" : ", ") + plain_text(item);
    return out;
  }
  for (const auto& [key, item] : v.items())
    out += (out.empty() ? "" : "; ") + key + " " + plain_text(item);
  return out;
}

std::string json_table_html(const Json& value) {
  auto cell = [](const Json& v) {
    if (v.is_number()) return "<td>" + esc(fmt(v.get<double>(), 5)) + "</td>";
    return "<td class=\"name\">" + esc(plain_text(v)) + "</td>";
  };
  std::string out = "<table>";
  if (value.is_object()) {
    for (const auto& [key, v] : value.items())
      out += "<tr><th class=\"name\">" + esc(key) + "</th>" + cell(v) + "</tr>";
  } else if (value.is_array()) {
    std::vector<std::string> keys;
    for (const auto& row : value)
      if (row.is_object())
        for (const auto& [key, v] : row.items())
          if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
    out += "<tr>";
    for (const auto& k : keys) out += "<th>" + esc(k) + "</th>";
    out += "</tr>";
    for (const auto& row : value) {
      out += "<tr>";
      if (row.is_object())
        for (const auto& k : keys) out += row.contains(k) ? cell(row[k]) : "<td></td>";
      else
        out += cell(row);
      out += "</tr>";
    }
  } else {
    out += "<tr>" + cell(value) + "</tr>";
  }
  return out + "</table>";
}

// ---------------------------------------------------------------------------------------
// Verdicts

std::vector<Verdict> calibration_verdicts(const Json& r) {
  using L = Verdict::Level;
  std::vector<Verdict> out;
  const std::string termination = text_of(r, "termination");
  if (termination == "converged")
    out.push_back({L::kGood, "The solver converged (" + text_of(r, "message") + ").", ""});
  else if (termination == "max_iterations")
    out.push_back({L::kWarning, "The solver stopped at its iteration limit before converging.",
                   "Re-run with a larger --max-iterations, or start from this result."});
  else
    out.push_back({L::kProblem,
                   "The solver did not reach a solution (" + termination + ": " +
                       text_of(r, "message") + "): the estimates below are not a calibration.",
                   "Check the data (outliers, wrong actuator columns) and the model's nominal "
                   "values; try --solver lm."});

  // Noise: sigma_hat against what the model states.
  const double sigma = num(member(r, "sigma_hat"));
  const std::string sigma_unit = text_of(r, "sigma_hat_unit");
  if (std::isfinite(sigma)) {
    if (sigma_unit == "reading_std") {
      if (sigma > 2)
        out.push_back({L::kWarning,
                       "The residuals are " + fmt(sigma, 3) +
                           " times the noise the model states (reading_std): the model does "
                           "not explain the data to the accuracy of the sensor.",
                       "Look for a fixed parameter at a wrong value (kincal observability "
                       "--sensitivity shows what each one would cost), outliers, or a "
                       "reading_std that is too optimistic."});
      else if (sigma < 0.5)
        out.push_back({L::kNote,
                       "The residuals are only " + fmt(sigma, 3) +
                           " times the stated reading_std: the sensor is better than the "
                           "model file says, or the fit has too few degrees of freedom.",
                       "State a smaller reading_std if the sensor's specification allows."});
      else
        out.push_back({L::kGood,
                       "The residuals match the stated sensor noise (sigma_hat = " + fmt(sigma, 3) +
                           " x reading_std).",
                       ""});
    } else {
      out.push_back({L::kNote,
                     "The noise estimated from the residuals is sigma_hat = " + fmt(sigma, 3) +
                         " " +
                         (sigma_unit == "mixed" ? "(mm and rad pooled, unweighted)" : sigma_unit) +
                         ". The model states no sensor noise, so kincal cannot tell whether "
                         "that is the sensor or a model error.",
                     "State your sensor's accuracy as reading_std in the model file: the report "
                     "then compares the residuals with it."});
    }
  }

  // Conditioning.
  const Json& id = member(r, "identifiability");
  const double cond = num(member(id, "condition_number"));
  const int n = member(id, "parameters").is_number() ? member(id, "parameters").get<int>() : 0;
  const int rank =
      member(id, "numerical_rank").is_number() ? member(id, "numerical_rank").get<int>() : n;
  if (rank < n)
    out.push_back({L::kProblem,
                   "The data determine only " + std::to_string(rank) + " of " + std::to_string(n) +
                       " directions in parameter space.",
                   "Fix parameters you know (--fix), or measure configurations that move the "
                   "listed combinations."});
  else if (cond > 1e5)
    out.push_back({L::kWarning,
                   "The identification is severely ill-conditioned (condition number " +
                       fmt(cond, 2) +
                       "): along its weakest directions the sensor noise is amplified by that "
                       "much, so some parameters are hardly determined.",
                   "Measure configurations that spread further (kincal observability --poses "
                   "60 --config-range R shows the effect before you measure), or fix "
                   "parameters known from other measurements."});
  else if (cond > 1e3)
    out.push_back({L::kNote,
                   "The identification is ill-conditioned (condition number " + fmt(cond, 2) +
                       "): weakly determined directions amplify the sensor noise.",
                   "More and more widely spread configurations shrink the standard deviations."});
  else if (std::isfinite(cond))
    out.push_back(
        {L::kGood,
         "The identification is well conditioned (condition number " + fmt(cond, 3) + ").", ""});

  // The least determined parameters, per unit.
  const Json& params = member(r, "parameters");
  std::map<std::string, std::vector<std::pair<double, std::string>>> by_unit;
  int not_significant = 0, counted = 0;
  if (params.is_array())
    for (const auto& p : params) {
      const double s = num(member(p, "std"));
      if (!std::isfinite(s)) continue;
      by_unit[text_of(p, "unit")].push_back({s, text_of(p, "name")});
      double change = num(member(p, "estimate")) - num(member(p, "nominal"));
      if (text_of(p, "unit") == "rad") change = std::remainder(change, 2 * kPi);
      ++counted;
      if (std::abs(change) < s) ++not_significant;
    }
  for (auto& [unit, list] : by_unit) {
    std::sort(list.rbegin(), list.rend());
    const DisplayUnit du = display_unit(unit);
    std::string names;
    for (std::size_t i = 0; i < list.size() && i < 3; ++i)
      names += std::string(i ? ", " : "") + list[i].second + " (std " +
               fmt(list[i].first * du.scale, 3) + " " + du.label + ")";
    // Noise amplification is measurable when the parameters and sigma_hat share a unit.
    const bool same_unit = sigma_unit == unit && std::isfinite(sigma) && sigma > 0;
    const double amplification = same_unit ? list[0].first / sigma : NAN;
    const bool weak = same_unit && amplification > 100;
    out.push_back({weak ? L::kWarning : L::kNote,
                   "Least determined (" + du.label + "): " + names + "." +
                       (weak ? " The largest is " + fmt(amplification, 2) +
                                   " times the noise: the data does not determine it to better "
                                   "than that."
                             : ""),
                   weak ? "Fix it (--fix " + list[0].second +
                              ") at a value measured another way, or add configurations "
                              "that spread further."
                        : ""});
  }
  if (counted && not_significant)
    out.push_back({L::kNote,
                   std::to_string(not_significant) + " of " + std::to_string(counted) +
                       " corrections are smaller than their own standard deviation: the data "
                       "cannot tell them from no correction.",
                   ""});

  // Correlations of +-1.
  const Json& corr = member(r, "correlation");
  std::vector<std::string> pairs;
  int near_one = 0;
  if (corr.is_array() && params.is_array())
    for (std::size_t i = 0; i < corr.size() && i < params.size(); ++i)
      for (std::size_t j = 0; j < i && j < corr[i].size(); ++j) {
        const double c = num(corr[i][j]);
        if (std::isfinite(c) && std::abs(c) >= 0.999) {
          ++near_one;
          if (pairs.size() < 3)
            pairs.push_back(text_of(params[i], "name") + " and " + text_of(params[j], "name") +
                            " (" + (c > 0 ? "+" : "") + fmt(c, 4) + ")");
        }
      }
  if (near_one) {
    std::string list;
    for (std::size_t i = 0; i < pairs.size(); ++i) list += (i ? "; " : "") + pairs[i];
    out.push_back({L::kWarning,
                   std::to_string(near_one) + " pair(s) of parameters are correlated at " +
                       "\xC2\xB1" + "0.999 or more: " + list +
                       ". The data determines only a combination of each pair, not the two.",
                   "Fix one of each pair (--fix) if it is known, or measure configurations that "
                   "move them differently."});
  }

  // Outliers.
  std::vector<std::string> lines;
  if (member(r, "residuals").is_array())
    for (const auto& row : member(r, "residuals"))
      if (member(row, "outlier").is_boolean() && row["outlier"].get<bool>())
        lines.push_back(text_of(row, "line"));
  if (!lines.empty()) {
    std::string list;
    for (std::size_t i = 0; i < lines.size() && i < 10; ++i) list += (i ? ", " : "") + lines[i];
    if (lines.size() > 10) list += ", ...";
    const std::string loss = text_of(r, "loss");
    const std::string delta = std::isfinite(sigma) && sigma_unit != "mixed"
                                  ? " (delta about 2-3 times the noise, e.g. " +
                                        fmt(2.5 * sigma, 2) +
                                        (sigma_unit == "reading_std" ? " x reading_std" : "") + ")"
                                  : "";
    out.push_back(
        {L::kWarning,
         std::to_string(lines.size()) + " configuration(s) flagged as outliers: line(s) " + list +
             ". " + text_of(r, "outlier_meaning") + ".",
         loss == "none" || loss.empty()
             ? "Check those rows; if they are gross errors, re-run with --loss huber:" +
                   std::string(std::isfinite(sigma) && sigma_unit != "reading_std" &&
                                       sigma_unit != "mixed"
                                   ? fmt(2.5 * sigma, 2)
                                   : "DELTA") +
                   delta + ", then --loss cauchy from that result."
             : "The fit already used --loss " + loss + "; check those rows, or drop them."});
  }
  if (member(r, "skipped_lines").is_array() && !r["skipped_lines"].empty())
    out.push_back({L::kNote,
                   std::to_string(r["skipped_lines"].size()) +
                       " row(s) were dropped because the starting model cannot reach them "
                       "(--skip-bad-rows).",
                   ""});
  // Accuracy in the field's terms, measured: for a point-measuring sensor it replaces the
  // workspace prediction, whose "nominal" figure comes from assumed tolerances.
  const Json& position = member(r, "position_error_mm");
  if (position.is_object()) {
    const double before = num(member(member(position, "before"), "mean"));
    const double after = num(member(member(position, "after"), "mean"));
    const double registration = num(member(member(position, "registration_only"), "mean"));
    const Json& cv = member(r, "cross_validation");
    const double held_out = num(member(member(cv, "position_error_mm"), "mean"));
    const double held_out_registration =
        num(member(member(cv, "registration_only_position_error_mm"), "mean"));
    std::string text =
        "Mean 3-D position error of the measured point on the calibration data: " + fmt(before, 4) +
        " mm before, " +
        (std::isfinite(registration)
             ? fmt(registration, 4) + " mm with registration only (frames fitted), "
             : std::string()) +
        fmt(after, 4) + " mm calibrated.";
    if (std::isfinite(held_out))
      text += " Held out (" + text_of(cv, "folds") +
              "-fold cross-validation): " + fmt(held_out, 4) + " mm calibrated" +
              (std::isfinite(held_out_registration)
                   ? ", " + fmt(held_out_registration, 4) + " mm registration only"
                   : std::string()) +
              ".";
    const bool better = after < before && (!std::isfinite(held_out) || held_out < before);
    if (!std::isfinite(before) || !std::isfinite(after))
      out.push_back(
          {L::kNote,
           "The 3-D position error before and after could not both be computed (" + text + ")",
           ""});
    else
      out.push_back({better ? L::kGood : L::kProblem, text,
                     better ? (std::isfinite(held_out)
                                   ? ""
                                   : "Check it on held-out data: kincal validate, or --folds K.")
                            : "The calibration does not reduce the error: check the data, the "
                              "free parameters and the model."});
  }
  // The predicted pose error of the estimate against the nominal model (experiment design).
  const Json& predicted = member(r, "predicted_pose_error");
  if (!position.is_object() && predicted.is_object() && member(predicted, "computed") == true) {
    const double calibrated = num(member(member(predicted, "calibrated"), "position_rms_mm"));
    const double nominal = num(member(member(predicted, "nominal"), "position_rms_mm"));
    if (member(predicted, "expected_to_beat_nominal") == true)
      out.push_back({L::kGood,
                     "Predicted position error over the workspace: " + fmt(calibrated, 3) +
                         " mm RMS, against " + fmt(nominal, 3) + " mm for the nominal model.",
                     ""});
    else
      out.push_back({L::kProblem,
                     "This calibration is NOT expected to beat the nominal model: predicted "
                     "position error " +
                         fmt(calibrated, 3) + " mm RMS against " + fmt(nominal, 3) +
                         " mm for the nominal model.",
                     "Do not load it as it is: measure configurations chosen by kincal design, "
                     "add what you know as prior_std, or fix the weakly determined parameters."});
  }
  if (const auto target = target_verdict(member(r, "target"))) out.push_back(*target);
  // What readings that measure no point cannot show (issue: a single gauge).
  if (member(r, "pose_accuracy_shown") == false)
    out.push_back({L::kNote,
                   "The readings measure no point of the mechanism: residuals that agree, "
                   "fitted or held out, do not confirm the pose accuracy, and the predicted "
                   "pose error comes from the model, not from a measured pose.",
                   "To check the pose, measure configurations with a point or pose tracker, or "
                   "with the gauge in a second placement, and run kincal validate on them."});
  if (member(r, "warnings").is_array())
    for (const auto& w : r["warnings"]) out.push_back({L::kWarning, text_of(w), ""});
  return out;
}

// ---------------------------------------------------------------------------------------
// Charts

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

std::string residuals_html(const Json& r) {
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

std::string parameters_html(const Json& r) {
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

std::string correlation_html(const Json& r) {
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

}  // namespace

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
           (cond < 1e3   ? "That is a well-conditioned calibration."
            : cond < 1e5 ? "That is ill-conditioned: expect standard deviations far above the "
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

namespace {

std::string outliers_html(const Json& r) {
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

std::string summary_html(const Json& r) {
  std::string out = "<table>";
  auto row = [&](const std::string& key, const std::string& value) {
    out += "<tr><th class=\"name\">" + esc(key) + "</th><td class=\"name\">" + esc(value) +
           "</td></tr>";
  };
  row("model", text_of(r, "model"));
  row("data", text_of(r, "data"));
  row("solver", text_of(r, "solver") + ", loss " + text_of(r, "loss"));
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

}  // namespace

std::string render_calibration_html(const Json& r) {
  HtmlPage page("kincal calibration report: " + text_of(r, "model") + " from " +
                text_of(r, "data"));
  const std::vector<Verdict> verdicts = calibration_verdicts(r);
  std::string next;
  for (const auto& v : verdicts)
    if (!v.action.empty()) next += "<li>" + esc(v.action) + "</li>";
  page.add_section(
      "verdicts", "Verdicts",
      verdicts_html(verdicts) + (next.empty() ? "<p>Nothing to do: load the calibrated model.</p>"
                                              : "<h3>What to do next</h3><ol>" + next + "</ol>"));
  page.add_section("summary", "Summary", summary_html(r));
  page.add_section("residuals", "Residuals", residuals_html(r));
  page.add_section("parameters", "Parameter corrections", parameters_html(r));
  page.add_section("correlation", "Correlations", correlation_html(r));
  page.add_section("identifiability", "Identifiability", identifiability_html(r));
  page.add_section("outliers", "Outliers", outliers_html(r));
  if (r.contains("position_error_mm") && r["position_error_mm"].is_object())
    page.add_section("position-error", "3-D position error of the measured point",
                     measured_position_error_html(r));
  if (r.contains("predicted_pose_error") && r["predicted_pose_error"].is_object())
    page.add_section(
        "pose-accuracy", "Predicted pose accuracy",
        pose_accuracy_html(
            r["predicted_pose_error"],
            {{"calibrated", "calibrated"}, {"nominal", "nominal model (assumed spread)"}},
            member(r, "target")) +
            (member(r, "pose_accuracy_shown") == false
                 ? "<p class=\"note\">" + esc(text_of(r, "pose_accuracy_note")) + ".</p>"
                 : std::string()));
  if (r.contains("sensitivity"))
    page.add_section(
        "sensitivity", "Sensitivity to fixed parameters",
        sensitivity_html(r["sensitivity"], num(member(member(r, "target"), "position_mm"))));
  if (member(r, "warnings").is_array() && !r["warnings"].empty()) {
    std::string list = "<ul>";
    for (const auto& w : r["warnings"]) list += "<li>" + esc(text_of(w)) + "</li>";
    page.add_section("warnings", "Warnings", list + "</ul>");
  }
  return page.str();
}

}  // namespace kincal::cli
