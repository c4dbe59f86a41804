// The verdicts of the calibration report's page (calibration_verdicts, cli/html_report.hpp):
// each finding of the report in plain words, with what to do next.

#include <algorithm>
#include <cmath>
#include <map>

#include "kincal/cli/html_pose_accuracy.hpp"
#include "kincal/cli/html_report.hpp"
#include "kincal/cli/html_values.hpp"
#include "kincal/framework/analysis/identifiability.hpp"

namespace kincal::cli {

using namespace html_values;

std::vector<Verdict> calibration_verdicts(const Json& r) {
  using L = Verdict::Level;
  std::vector<Verdict> out;
  // The library's verdict first (framework/analysis/calibration_verdict.hpp): the same
  // findings the text and JSON reports carry, with the same thresholds.
  const Json& verdict = member(r, "verdict");
  if (member(verdict, "findings").is_array())
    for (const auto& f : verdict["findings"]) {
      const std::string level = text_of(f, "level");
      out.push_back({level == "good"          ? L::kGood
                     : level == "warning"     ? L::kWarning
                     : level == "do_not_load" ? L::kProblem
                                              : L::kNote,
                     text_of(f, "text"), text_of(f, "advice")});
    }

  // Several starts (--starts): whether they agree on one minimum.
  const Json& starts = member(r, "starts");
  const double start_count = num(member(starts, "count"));
  if (start_count > 1) {
    const Json& minima = member(starts, "minima");
    const std::size_t distinct = minima.is_array() ? minima.size() : 0;
    const std::string n = fmt(start_count, 6);
    if (distinct > 1) {
      std::string costs;
      for (std::size_t i = 0; i < distinct && i < 5; ++i)
        costs += std::string(i ? ", " : "") + fmt(num(member(minima[i], "cost")), 4);
      const double best = num(member(starts, "best_start"));
      const double best_reached = member(minima[0], "starts").size();
      out.push_back({L::kWarning,
                     "The " + n + " starts ended in " + std::to_string(distinct) +
                         " distinct minima (costs " + costs + (distinct > 5 ? ", ..." : "") +
                         "); the estimate is the lowest, reached by " + fmt(best_reached, 6) +
                         " of them" +
                         (best != 0 ? ", and not from the model's values (start 0)" : "") + ".",
                     std::string("The data do not single out one geometry: minima whose costs "
                                 "differ by about the noise fit equally well, and the lowest is "
                                 "not necessarily the closest (docs/benchmarks.md). Narrow the "
                                 "tolerances (param_error, prior_std) or measure more "
                                 "configurations.") +
                         (best_reached == 1 ? " Only one start reached the lowest: more --starts "
                                              "may find another."
                                            : "")});
    } else if (distinct == 1) {
      out.push_back(
          {L::kGood, "All " + n + " starts that reached a solution ended at one minimum.", ""});
    }
  }

  // The noise is the verdict's "fit" finding; sigma_hat is still needed below.
  const double sigma = num(member(r, "sigma_hat"));
  const std::string sigma_unit = text_of(r, "sigma_hat_unit");

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
  else if (cond > kSeverelyIllConditioned)
    out.push_back({L::kWarning,
                   "The identification is severely ill-conditioned (condition number " +
                       fmt(cond, 2) +
                       "): along its weakest directions the sensor noise is amplified by that "
                       "much, so some parameters are hardly determined.",
                   "Measure configurations that spread further (kincal observability --poses "
                   "60 --config-range R shows the effect before you measure), or fix "
                   "parameters known from other measurements."});
  else if (cond > kIllConditioned)
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
    const double located = num(member(member(position, "nominal_point_located"), "mean"));
    std::string text =
        "Mean 3-D position error of the measured point on the calibration data: " + fmt(before, 4) +
        " mm before, " +
        (std::isfinite(located)
             ? fmt(located, 4) + " mm for the nominal geometry with the measured point located, "
             : std::string()) +
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
      // The figures; a calibration that does not reduce the error is the verdict's finding.
      out.push_back({better ? L::kGood : L::kNote, text,
                     better && !std::isfinite(held_out)
                         ? "Check it on held-out data: kincal validate, or --folds K."
                         : ""});
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
    // Not expected to beat nominal: the verdict's "accuracy" finding says so.
  }
  // A target not met is the verdict's "target" finding.
  if (const auto target = target_verdict(member(r, "target")))
    if (target->level != L::kProblem) out.push_back(*target);
  // What readings that measure no point cannot show (issue: a single gauge).
  if (member(r, "pose_accuracy_shown") == false)
    out.push_back({L::kNote,
                   "The readings measure no point of the mechanism: residuals that agree, "
                   "fitted or held out, do not confirm the pose accuracy, and the predicted "
                   "pose error comes from the model, not from a measured pose.",
                   "To check the pose, measure configurations with a point or pose tracker, or "
                   "with the gauge in a second placement, and run kincal validate on them."});
  // The report's warnings are the verdict's "data" findings.
  return out;
}

}  // namespace kincal::cli
