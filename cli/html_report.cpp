#include "kincal/cli/html_report.hpp"

#include <algorithm>
#include <cmath>

#include "kincal/cli/calibration_report_sections.hpp"
#include "kincal/cli/html_pose_accuracy.hpp"
#include "kincal/cli/html_sensitivity.hpp"
#include "kincal/cli/html_values.hpp"
#include "kincal/cli/svg_plot.hpp"

namespace kincal::cli {

using namespace html_values;

namespace {

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
  page.add_section("summary", "Summary", calibration_summary_html(r));
  page.add_section("residuals", "Residuals", calibration_residuals_html(r));
  page.add_section("parameters", "Parameter corrections", calibration_parameters_html(r));
  const std::string constraints = calibration_constraints_html(r);
  if (!constraints.empty()) page.add_section("constraints", "Constraints", constraints);
  page.add_section("correlation", "Correlations", calibration_correlation_html(r));
  page.add_section("identifiability", "Identifiability", identifiability_html(r));
  page.add_section("outliers", "Outliers", calibration_outliers_html(r));
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
