// The page of an identifiability analysis (observability_html, pages.hpp).

#include <cmath>
#include <vector>

#include "kincal/framework/report/html_page.hpp"
#include "kincal/framework/report/pages.hpp"
#include "kincal/framework/report/sections.hpp"

namespace kincal::report {

namespace {

using L = Finding::Level;

std::vector<Finding> observability_findings(const ObservabilityResult& result,
                                            const std::optional<SensitivityResult>& sensitivity) {
  const Identifiability& id = result.identifiability;
  std::vector<Finding> out;
  const double n = id.num_parameters, rank = id.numerical_rank, m = id.num_residuals,
               cond = finite_or_nan(id.condition_number);
  if (m < n)
    out.push_back({"readings", L::kDoNotLoad,
                   "Fewer readings (" + fmt(m, 9) + ") than free parameters (" + fmt(n, 9) + ").",
                   "Measure more configurations."});
  if (rank < n) {
    const double with_prior = id.has_prior() ? id.numerical_rank_with_prior : NAN;
    if (std::isfinite(with_prior) && with_prior >= n)
      out.push_back({"rank", L::kNote,
                     "The data determine " + fmt(rank, 9) + " of " + fmt(n, 9) +
                         " directions; the prior determines the rest.",
                     ""});
    else
      out.push_back({"rank", L::kDoNotLoad,
                     "The data determine only " + fmt(rank, 9) + " of " + fmt(n, 9) +
                         " directions in parameter space: calibrating these parameters from "
                         "such data cannot succeed.",
                     "Fix parameters you know (--fix), or measure configurations that move the "
                     "combinations listed below."});
  } else if (cond > kSeverelyIllConditioned) {
    out.push_back({"conditioning", L::kWarning,
                   "All " + fmt(n, 9) +
                       " directions are determined, but the identification is "
                       "severely ill-conditioned (condition number " +
                       fmt(cond, 3) + ").",
                   "Spread the configurations further (--config-range) or fix parameters known "
                   "from other measurements."});
  } else if (std::isfinite(cond)) {
    out.push_back({"conditioning", cond > kIllConditioned ? L::kNote : L::kGood,
                   "All " + fmt(n, 9) + " free parameters are determined (condition number " +
                       fmt(cond, 3) + ").",
                   ""});
  }
  if (sensitivity) {
    double worst = 0;
    std::string name;
    for (const auto& row : sensitivity->rows)
      if (std::isfinite(row.position_max) && row.position_max > worst)
        worst = row.position_max, name = row.name;
    if (!name.empty())
      out.push_back({"sensitivity", L::kNote,
                     "Of the fixed parameters, an error in " + name +
                         " leaves the largest pose "
                         "error after calibration: up to " +
                         fmt(worst, 3) + " mm.",
                     "Measure it another way, or free it, if that is more than you can accept."});
  }
  return out;
}

}  // namespace

std::string observability_html(const ObservabilityResult& result,
                               const std::optional<SensitivityResult>& sensitivity) {
  const Identifiability& id = result.identifiability;
  HtmlPage page("kincal observability: " + result.model_file + " on " + result.source);
  page.add_section("verdicts", "Verdicts",
                   findings_html(observability_findings(result, sensitivity)));
  std::string summary = "<table>";
  summary += summary_row("model", result.model_file);
  summary +=
      summary_row("configurations", fmt(result.configurations, 9) + " (" + result.source + ")");
  summary += summary_row("readings", fmt(id.num_residuals, 9));
  summary += summary_row("free parameters", fmt(id.num_parameters, 9));
  summary += summary_row("numerical rank", fmt(id.numerical_rank, 9) + " (threshold " +
                                               fmt(id.rcond, 3) + " x the largest singular value)");
  summary += "</table>";
  page.add_section("summary", "Summary", summary);
  page.add_section("identifiability", "Identifiability", identifiability_html(id));
  if (id.has_prior()) {
    std::string share =
        "<table><tr><th class=\"name\">parameter</th><th>determined by the data (%)</th>"
        "<th>by the prior (%)</th></tr>";
    for (int i = 0; i < id.data_share.size(); ++i)
      share += "<tr><td class=\"name\">" + esc(id.names[static_cast<std::size_t>(i)]) +
               "</td><td>" + fmt(100 * id.data_share[i], 3) + "</td><td>" +
               fmt(100 * (1 - id.data_share[i]), 3) + "</td></tr>";
    page.add_section("prior", "Data and prior", share + "</table>");
  }
  if (!result.calibrate_keeps.empty()) {
    std::string keeps = "<p>calibrate (without --free/--fix) keeps these parameters free:";
    for (const auto& name : result.calibrate_keeps) keeps += " <code>" + esc(name) + "</code>";
    keeps += "</p><ul>";
    for (const auto& line : result.null_directions) keeps += "<li>" + esc(line) + "</li>";
    page.add_section("keeps", "What calibrate would keep", keeps + "</ul>");
  }
  if (sensitivity)
    page.add_section("sensitivity", "Sensitivity to fixed parameters",
                     sensitivity_html(*sensitivity, NAN));
  return page.str();
}

}  // namespace kincal::report
