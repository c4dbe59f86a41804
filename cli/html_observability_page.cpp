// The page of `kincal observability --html` (cli/html_pages.hpp).

#include <cmath>
#include <vector>

#include "kincal/cli/html_pages.hpp"
#include "kincal/cli/html_report.hpp"
#include "kincal/cli/html_sensitivity.hpp"
#include "kincal/cli/html_values.hpp"
#include "kincal/cli/svg_plot.hpp"
#include "kincal/framework/analysis/identifiability.hpp"

namespace kincal::cli {

namespace {

using namespace html_values;
using L = Verdict::Level;

std::vector<Verdict> observability_verdicts(const Json& o) {
  std::vector<Verdict> out;
  const double n = number_at(o, "parameters"), rank = number_at(o, "numerical_rank"),
               m = number_at(o, "residuals"), cond = number_at(o, "condition_number");
  if (m < n)
    out.push_back({L::kProblem,
                   "Fewer readings (" + fmt(m, 9) + ") than free parameters (" + fmt(n, 9) + ").",
                   "Measure more configurations."});
  if (rank < n) {
    const double with_prior = number_at(o, "numerical_rank_with_prior");
    if (std::isfinite(with_prior) && with_prior >= n)
      out.push_back({L::kNote,
                     "The data determine " + fmt(rank, 9) + " of " + fmt(n, 9) +
                         " directions; the prior determines the rest.",
                     ""});
    else
      out.push_back({L::kProblem,
                     "The data determine only " + fmt(rank, 9) + " of " + fmt(n, 9) +
                         " directions in parameter space: calibrating these parameters from "
                         "such data cannot succeed.",
                     "Fix parameters you know (--fix), or measure configurations that move the "
                     "combinations listed below."});
  } else if (cond > kSeverelyIllConditioned) {
    out.push_back({L::kWarning,
                   "All " + fmt(n, 9) +
                       " directions are determined, but the identification is "
                       "severely ill-conditioned (condition number " +
                       fmt(cond, 3) + ").",
                   "Spread the configurations further (--config-range) or fix parameters known "
                   "from other measurements."});
  } else if (std::isfinite(cond)) {
    out.push_back({cond > kIllConditioned ? L::kNote : L::kGood,
                   "All " + fmt(n, 9) + " free parameters are determined (condition number " +
                       fmt(cond, 3) + ").",
                   ""});
  }
  if (member(o, "sensitivity").is_array()) {
    double worst = 0;
    std::string name;
    for (const auto& row : o["sensitivity"]) {
      const double v = number_at(row, "position_max_mm");
      if (std::isfinite(v) && v > worst) worst = v, name = text_at(row, "name");
    }
    if (!name.empty())
      out.push_back({L::kNote,
                     "Of the fixed parameters, an error in " + name +
                         " leaves the largest pose "
                         "error after calibration: up to " +
                         fmt(worst, 3) + " mm.",
                     "Measure it another way, or free it, if that is more than you can accept."});
  }
  return out;
}

}  // namespace

std::string render_observability_html(const Json& o) {
  HtmlPage page("kincal observability: " + text_at(o, "model") + " on " + text_at(o, "source"));
  page.add_section("verdicts", "Verdicts", verdicts_html(observability_verdicts(o)));
  std::string summary = "<table>";
  auto row = [&](const std::string& key, const std::string& value) {
    summary += "<tr><th class=\"name\">" + esc(key) + "</th><td class=\"name\">" + esc(value) +
               "</td></tr>";
  };
  row("model", text_at(o, "model"));
  row("configurations", fmt(number_at(o, "configurations"), 9) + " (" + text_at(o, "source") + ")");
  row("readings", fmt(number_at(o, "residuals"), 9));
  row("free parameters", fmt(number_at(o, "parameters"), 9));
  row("numerical rank", fmt(number_at(o, "numerical_rank"), 9) + " (threshold " +
                            fmt(number_at(o, "rcond"), 3) + " x the largest singular value)");
  summary += "</table>";
  page.add_section("summary", "Summary", summary);
  page.add_section("identifiability", "Identifiability",
                   identifiability_html({{"identifiability", o}}));
  if (member(o, "data_share").is_array()) {
    std::string share =
        "<table><tr><th class=\"name\">parameter</th><th>determined by the data (%)</th>"
        "<th>by the prior (%)</th></tr>";
    for (const auto& s : o["data_share"])
      share += "<tr><td class=\"name\">" + esc(text_at(s, "name")) + "</td><td>" +
               fmt(100 * number_at(s, "data_share"), 3) + "</td><td>" +
               fmt(100 * number_at(s, "prior_share"), 3) + "</td></tr>";
    page.add_section("prior", "Data and prior", share + "</table>");
  }
  if (member(o, "calibrate_keeps").is_array()) {
    std::string keeps = "<p>calibrate (without --free/--fix) keeps these parameters free:";
    for (const auto& name : o["calibrate_keeps"])
      keeps += " <code>" + esc(plain_text(name)) + "</code>";
    keeps += "</p><ul>";
    for (const auto& line : member(o, "null_directions"))
      keeps += "<li>" + esc(plain_text(line)) + "</li>";
    page.add_section("keeps", "What calibrate would keep", keeps + "</ul>");
  }
  if (o.contains("sensitivity"))
    page.add_section("sensitivity", "Sensitivity to fixed parameters",
                     sensitivity_html(o["sensitivity"], NAN));
  return page.str();
}

}  // namespace kincal::cli
