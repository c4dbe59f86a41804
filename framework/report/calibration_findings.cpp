// The calibration page's findings (calibration_page_findings, calibration_page.hpp): the
// verdict's, then each further finding of the result in plain words, with what to do next.

#include <algorithm>
#include <cmath>
#include <map>

#include "kincal/framework/analysis/starts_report.hpp"
#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/report/calibration_page.hpp"
#include "kincal/framework/report/html_page.hpp"
#include "kincal/framework/report/sections.hpp"

namespace kincal::report {

namespace {

using L = Finding::Level;

// A count as the pages have always written it (5 significant digits).
std::string count_text(double n) { return fmt(n, 5); }

void add_starts(const StartsReport& starts, std::vector<Finding>& out) {
  const MultiStartResult& m = starts.result;
  if (m.starts.size() <= 1) return;
  const std::size_t distinct = m.minima.size();
  const std::string n = fmt(static_cast<double>(m.starts.size()), 6);
  if (distinct > 1) {
    std::string costs;
    for (std::size_t i = 0; i < distinct && i < 5; ++i)
      costs += std::string(i ? ", " : "") + fmt(m.minima[i].cost, 4);
    const double best = m.best_start;
    const double best_reached = m.minima[0].starts.size();
    out.push_back({"starts", L::kWarning,
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
    out.push_back({"starts", L::kGood,
                   "All " + n + " starts that reached a solution ended at one minimum.", ""});
  }
}

void add_conditioning(const Identifiability& id, std::vector<Finding>& out) {
  const double cond = finite_or_nan(id.condition_number);
  const int n = id.num_parameters, rank = id.numerical_rank;
  if (rank < n)
    out.push_back({"conditioning", L::kDoNotLoad,
                   "The data determine only " + std::to_string(rank) + " of " + std::to_string(n) +
                       " directions in parameter space.",
                   "Fix parameters you know (--fix), or measure configurations that move the "
                   "listed combinations."});
  else if (cond > kSeverelyIllConditioned)
    out.push_back({"conditioning", L::kWarning,
                   "The identification is severely ill-conditioned (condition number " +
                       fmt(cond, 2) +
                       "): along its weakest directions the sensor noise is amplified by that "
                       "much, so some parameters are hardly determined.",
                   "Measure configurations that spread further (kincal observability --poses "
                   "60 --config-range R shows the effect before you measure), or fix "
                   "parameters known from other measurements."});
  else if (cond > kIllConditioned)
    out.push_back({"conditioning", L::kNote,
                   "The identification is ill-conditioned (condition number " + fmt(cond, 2) +
                       "): weakly determined directions amplify the sensor noise.",
                   "More and more widely spread configurations shrink the standard deviations."});
  else if (std::isfinite(cond))
    out.push_back(
        {"conditioning", L::kGood,
         "The identification is well conditioned (condition number " + fmt(cond, 3) + ").", ""});
}

// The least determined parameters per unit, and the corrections within their own std.
void add_parameters(const CalibrationReport& r, std::vector<Finding>& out) {
  const double sigma = finite_or_nan(r.uncertainty.sigma);
  const std::string unit_of_sigma = sigma_unit(r);
  std::map<std::string, std::vector<std::pair<double, std::string>>> by_unit;
  int not_significant = 0, counted = 0;
  for (std::size_t i = 0; i < r.names.size(); ++i) {
    const double s =
        r.uncertainty.std.size() ? finite_or_nan(r.uncertainty.std[static_cast<int>(i)]) : NAN;
    if (!std::isfinite(s)) continue;
    by_unit[r.units[i]].push_back({s, r.names[i]});
    double change = r.estimate[static_cast<int>(i)] - r.nominal[static_cast<int>(i)];
    if (r.units[i] == "rad") change = std::remainder(change, 2 * kPi);
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
    const bool same_unit = unit_of_sigma == unit && std::isfinite(sigma) && sigma > 0;
    const double amplification = same_unit ? list[0].first / sigma : NAN;
    const bool weak = same_unit && amplification > kWeakParameterAmplification;
    out.push_back({"least_determined", weak ? L::kWarning : L::kNote,
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
    out.push_back({"not_significant", L::kNote,
                   std::to_string(not_significant) + " of " + std::to_string(counted) +
                       " corrections are smaller than their own standard deviation: the data "
                       "cannot tell them from no correction.",
                   ""});
}

void add_correlations(const CalibrationReport& r, std::vector<Finding>& out) {
  const MatrixXd& corr = r.uncertainty.correlation;
  std::vector<std::string> pairs;
  int near_one = 0;
  for (int i = 0; i < corr.rows() && i < static_cast<int>(r.names.size()); ++i)
    for (int j = 0; j < i && j < corr.cols(); ++j) {
      const double c = finite_or_nan(corr(i, j));
      if (std::isfinite(c) && std::abs(c) >= kCorrelatedPair) {
        ++near_one;
        if (pairs.size() < 3)
          pairs.push_back(r.names[i] + " and " + r.names[j] + " (" + (c > 0 ? "+" : "") +
                          fmt(c, 4) + ")");
      }
    }
  if (!near_one) return;
  std::string list;
  for (std::size_t i = 0; i < pairs.size(); ++i) list += (i ? "; " : "") + pairs[i];
  out.push_back({"correlation", L::kWarning,
                 std::to_string(near_one) + " pair(s) of parameters are correlated at " +
                     "\xC2\xB1" + fmt(kCorrelatedPair, 4) + " or more: " + list +
                     ". The data determines only a combination of each pair, not the two.",
                 "Fix one of each pair (--fix) if it is known, or measure configurations that "
                 "move them differently."});
}

void add_outliers(const CalibrationReport& r, std::vector<Finding>& out) {
  std::vector<std::string> lines;
  for (int c = 0; c < r.residuals.rows(); ++c)
    if (r.outlier[c]) lines.push_back(count_text(r.lines[c]));
  if (lines.empty()) return;
  const double sigma = finite_or_nan(r.uncertainty.sigma);
  const std::string unit_of_sigma = sigma_unit(r);
  std::string list;
  for (std::size_t i = 0; i < lines.size() && i < 10; ++i) list += (i ? ", " : "") + lines[i];
  if (lines.size() > 10) list += ", ...";
  const std::string& loss = r.loss;
  const std::string delta = std::isfinite(sigma) && unit_of_sigma != "mixed"
                                ? " (delta about 2-3 times the noise, e.g. " + fmt(2.5 * sigma, 2) +
                                      (unit_of_sigma == "reading_std" ? " x reading_std" : "") + ")"
                                : "";
  out.push_back(
      {"outliers", L::kWarning,
       std::to_string(lines.size()) + " configuration(s) flagged as outliers: line(s) " + list +
           ". " + outlier_meaning(r) + ".",
       loss == "none" || loss.empty()
           ? "Check those rows; if they are gross errors, re-run with --loss huber:" +
                 std::string(std::isfinite(sigma) && unit_of_sigma != "reading_std" &&
                                     unit_of_sigma != "mixed"
                                 ? fmt(2.5 * sigma, 2)
                                 : "DELTA") +
                 delta + ", then --loss cauchy from that result."
           : "The fit already used --loss " + loss + "; check those rows, or drop them."});
}

// Accuracy in the field's terms, measured: for a point-measuring sensor it replaces the
// workspace prediction, whose "nominal" figure comes from assumed tolerances.
void add_position_error(const CalibrationReport& r, std::vector<Finding>& out) {
  const double before = finite_or_nan(r.position_before.mean);
  const double after = finite_or_nan(r.position_after.mean);
  const double registration =
      r.registration.computed ? finite_or_nan(r.registration.position.mean) : NAN;
  const auto& cv = r.cross_validation;
  const bool held = cv.folds > 0 && cv.position.points > 0;
  const double held_out = held ? finite_or_nan(cv.position.mean) : NAN;
  const double held_out_registration = held ? finite_or_nan(cv.registration_position.mean) : NAN;
  const double located =
      r.point_located.computed ? finite_or_nan(r.point_located.position.mean) : NAN;
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
    text += " Held out (" + count_text(cv.folds) + "-fold cross-validation): " + fmt(held_out, 4) +
            " mm calibrated" +
            (std::isfinite(held_out_registration)
                 ? ", " + fmt(held_out_registration, 4) + " mm registration only"
                 : std::string()) +
            ".";
  const bool better = after < before && (!std::isfinite(held_out) || held_out < before);
  if (!std::isfinite(before) || !std::isfinite(after))
    out.push_back(
        {"position_error", L::kNote,
         "The 3-D position error before and after could not both be computed (" + text + ")", ""});
  else
    // The figures; a calibration that does not reduce the error is the verdict's finding.
    out.push_back({"position_error", better ? L::kGood : L::kNote, text,
                   better && !std::isfinite(held_out)
                       ? "Check it on held-out data: kincal validate, or --folds K."
                       : ""});
}

}  // namespace

std::vector<Finding> calibration_page_findings(const CalibrateResult& result,
                                               const CalibrationPageExtras& extras) {
  const CalibrationReport& r = result.report;
  // The library's verdict first: the same findings the text and JSON reports carry, with the
  // same thresholds.
  std::vector<Finding> out = result.verdict.findings;
  add_starts(result.starts, out);
  // The noise is the verdict's "fit" finding.
  add_conditioning(r.identifiability, out);
  add_parameters(r, out);
  add_correlations(r, out);
  add_outliers(r, out);
  if (!r.skipped_lines.empty())
    out.push_back({"skipped_rows", L::kNote,
                   std::to_string(r.skipped_lines.size()) +
                       " row(s) were dropped because the starting model cannot reach them "
                       "(--skip-bad-rows).",
                   ""});
  const bool measured_position = r.position_after.points > 0;
  if (measured_position) add_position_error(r, out);
  // The predicted pose error of the estimate against the nominal model (experiment design).
  const AccuracyComparison& predicted = r.predicted_accuracy;
  if (!measured_position && predicted.computed && predicted.expected_to_beat_nominal)
    out.push_back({"predicted_accuracy", L::kGood,
                   "Predicted position error over the workspace: " +
                       fmt(finite_or_nan(predicted.calibrated.position_rms), 3) +
                       " mm RMS, against " + fmt(finite_or_nan(predicted.nominal.position_rms), 3) +
                       " mm for the nominal model.",
                   ""});
  // Not expected to beat nominal: the verdict's "accuracy" finding says so. A target not met
  // is the verdict's "target" finding.
  if (extras.target) {
    const Finding target = target_finding(*extras.target);
    if (target.level != L::kDoNotLoad) out.push_back(target);
  }
  // What readings that measure no point cannot show (issue: a single gauge).
  if (!r.pose_accuracy_shown)
    out.push_back({"pose_not_shown", L::kNote,
                   "The readings measure no point of the mechanism: residuals that agree, "
                   "fitted or held out, do not confirm the pose accuracy, and the predicted "
                   "pose error comes from the model, not from a measured pose.",
                   "To check the pose, measure configurations with a point or pose tracker, or "
                   "with the gauge in a second placement, and run kincal validate on them."});
  // The report's warnings are the verdict's "data" findings.
  return out;
}

}  // namespace kincal::report
