// The verdict on a calibration, finding by finding (calibration_verdict.hpp).
#include "kincal/framework/analysis/calibration_verdict.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "kincal/framework/calibration/equivalent_solutions.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal {

namespace {

using L = Finding::Level;

std::string fmt(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

std::string percent(double share) { return fmt("%.0f", 100 * share) + " %"; }

void solver_finding(const CalibrationReport& r, std::vector<Finding>& out) {
  switch (r.summary.termination) {
    case TerminationType::kConverged:
      out.push_back({"solver", L::kGood, "The solver converged (" + r.summary.message + ").", ""});
      return;
    case TerminationType::kMaxIterations:
      out.push_back({"solver", L::kWarning,
                     "The solver stopped at its iteration limit before converging: the estimate "
                     "is where it stopped, not a minimum.",
                     "Re-run with a larger --max-iterations, or start from this result."});
      return;
    default:
      out.push_back({"solver", L::kDoNotLoad,
                     "The solver reached no solution (" +
                         std::string(to_string(r.summary.termination)) + ": " + r.summary.message +
                         ").",
                     "Check the data (outliers, wrong columns) and the model's starting values."});
  }
}

void branch_findings(const CalibrationReport& r, std::vector<Finding>& out) {
  if (!r.branch_mapped.empty()) {
    std::string list;
    for (const auto& mapped : r.branch_mapped) list += (list.empty() ? "" : "; ") + mapped;
    out.push_back({"branch", L::kNote,
                   "The solver ended on an equivalent solution away from the nominal values, "
                   "mapped back exactly (every prediction the same): " +
                       list + ".",
                   ""});
  }
  if (r.off_branch.empty()) return;
  std::string list;
  for (std::size_t i = 0; i < r.off_branch.size() && i < 4; ++i)
    list += (i ? "; " : "") + r.off_branch[i];
  if (r.off_branch.size() > 4) list += "; and " + std::to_string(r.off_branch.size() - 4) + " more";
  out.push_back(
      {"branch", L::kDoNotLoad,
       "Angles of the geometry lie on another branch than their nominal (more than pi/2 "
       "away): " +
           list +
           (r.branch_rejected.empty() ? std::string()
                                      : "; the map back, " + r.branch_rejected + ",") +
           ". An equivalent solution that the free parameters cannot map back exactly: exported "
           "as it is, it draws the links turned or mirrored.",
       "Start from values nearer the machine (the sensor's frame and the measured point: "
       "kincal model --point, or the frames in the model file), or fix the joints' zeros "
       "that turned (--fix), and calibrate again."});
}

void tolerance_finding(const CalibrationReport& r, std::vector<Finding>& out) {
  if (r.far_corrections.empty()) return;
  std::string list;
  bool assumed = false;
  for (std::size_t i = 0; i < r.far_corrections.size() && i < 4; ++i) {
    const auto& c = r.far_corrections[i];
    list += (i ? "; " : "") + c.name + " " + fmt("%+.4g", c.change) + " " + c.unit +
            " (tolerance " + fmt("%.3g", c.tolerance) + " " + c.unit +
            (c.assumed ? ", assumed" : "") + ")";
    assumed = assumed || c.assumed;
  }
  if (r.far_corrections.size() > 4)
    list += "; and " + std::to_string(r.far_corrections.size() - 4) + " more";
  out.push_back(
      {"tolerance", L::kDoNotLoad,
       "Corrections far beyond the geometry's tolerances (more than " +
           fmt("%.0f", kFarBeyondTolerance) + " times): " + list +
           ". The fit has absorbed something that is not the machine's geometry: a mirrored "
           "(left-handed) axis or swapped columns in the readings, readings in other units, "
           "rows that do not belong together, or an equivalent solution on another branch." +
           (assumed ? " (Where the model states no tolerance, kincal assumes 5 mm and 0.01 rad.)"
                    : ""),
       "Check the readings' axes and columns against the sensor's frame and the model's "
       "starting values; state the tolerances you know as param_error or prior_std."});
}

void fit_findings(const CalibrationReport& r, std::vector<Finding>& out) {
  const ResidualStructure& s = r.structure;
  if (!s.tested) {
    if (!s.not_tested.empty())
      out.push_back(
          {"fit", L::kNote, "The residuals' shape was not tested: " + s.not_tested + ".", ""});
    return;
  }
  bool unexplained = false;
  for (const auto& [unit, share] : s.unexplained_spread)
    if (share > kUnexplainedSpread) {
      unexplained = true;
      out.push_back(
          {"fit", L::kDoNotLoad,
           "The model leaves most of what the sensor saw unexplained: the typical residual "
           "(1.4826 x the median |residual|) is " +
               percent(share) + " of the readings' spread (" +
               fmt("%.4g", s.reading_spread.at(unit)) + " " + unit +
               "), where a calibration leaves its sensor's noise, a few hundredths at most.",
           "Check that each row's readings belong to its configuration (rows shuffled, shifted "
           "or from another session), the columns and their units."});
    }
  // Residuals that explain nothing have every shape: the rest would only repeat it.
  if (unexplained) return;
  const bool fixed = s.fixed_structured(), neighbours = s.neighbour_structured();
  if (fixed)
    out.push_back({"fit", L::kWarning,
                   percent(s.fixed_fraction) +
                       " of the residuals have the shape of a change of the fixed parameters (" +
                       s.dominant_fixed + " alone: " + percent(s.dominant_fixed_fraction) +
                       "): a frame frozen at a wrong value, or a fixed parameter that is wrong.",
                   "Free it (--free " + s.dominant_fixed +
                       ") or correct its value, and calibrate "
                       "again."});
  if (neighbours && !fixed)
    out.push_back(
        {"fit", L::kWarning,
         "The residuals vary smoothly with the configuration: " + percent(s.neighbour_fraction) +
             " of their variance is shared by neighbouring configurations (" +
             fmt("%.0f", s.neighbour_z) +
             " standard errors), which noise is not. The model misses something: a fixed "
             "parameter or frame, the readings' units or axes, or an effect it does not model.",
         "kincal observability --sensitivity shows what each fixed parameter would explain; "
         "check the frames and the units."});
  if (fixed || neighbours) return;
  const double sigma = r.uncertainty.sigma;
  if (!std::isfinite(sigma)) return;
  const std::string shape =
      "the residuals show no model error's structure (" +
      percent(std::max(0.0, s.neighbour_fraction)) +
      " of their variance shared by neighbouring configurations, where a model error shares "
      "more than " +
      percent(kNeighbourStructured) + ")";
  if (!r.weighted) {
    out.push_back({"fit", L::kNote,
                   "The noise estimated from the residuals is " + fmt("%.4g", sigma) + " " +
                       sigma_unit(r) + ", and " + shape +
                       ": they look like the set-up's noise, not a model error.",
                   "State it (or your sensor's accuracy) as reading_std in the model file: the "
                   "report then compares the residuals with it."});
    return;
  }
  if (sigma <= kNoiseAsStated) {
    out.push_back({"fit", L::kGood,
                   "The residuals are as the stated noise predicts (sigma_hat " +
                       fmt("%.3g", sigma) + " x reading_std), and " + shape + ".",
                   ""});
    return;
  }
  // Too few readings for the shape to clear the fit: then the stated noise decides, as a
  // chi-square would (the fit check), and the shape's figures are given for what they are.
  if (s.fixed_directions > 0 && s.fixed_test_dof < kMinShapeDegreesOfFreedom &&
      r.fit_check.too_large()) {
    out.push_back(
        {"fit", L::kWarning,
         "The readings scatter " + fmt("%.3g", sigma) + " times the stated noise (chi-square " +
             fmt("%.4g", r.fit_check.chi_square) + " on " +
             std::to_string(r.fit_check.degrees_of_freedom) + " degrees of freedom, " +
             "P(larger) " + fmt("%.2g", r.fit_check.p_larger) + "), and with " +
             std::to_string(s.fixed_test_dof) +
             " residual degree(s) of freedom beyond the free and fixed parameters their shape "
             "cannot tell the set-up's noise from a model error (the fixed parameters explain " +
             percent(s.fixed_fraction) + ", as noise would with P " + fmt("%.2g", s.fixed_p) + ").",
         "Measure more configurations, or check the fixed parameters (kincal observability "
         "--sensitivity) and reading_std."});
    return;
  }
  const bool far = sigma > kNoiseFarAboveStated;
  out.push_back({"fit", far ? L::kWarning : L::kNote,
                 "The readings scatter " + fmt("%.3g", sigma) +
                     " times the stated noise (reading_std), and " + shape +
                     (far ? ": far more than a sensor's datasheet is ever off; check the "
                            "readings' units and that each row's readings belong to it."
                          : ": that is the set-up's noise (the robot's repeatability, "
                            "temperature, the sensor's real accuracy), not a model error."),
                 far ? ""
                     : "State reading_std " + fmt("%.3g", sigma) +
                           " times larger if that is the set-up you calibrate with."});
}

void baseline_findings(const CalibrationReport& r, std::vector<Finding>& out) {
  const auto& b = r.registration;
  const bool positions = b.position.points > 0 && r.position_after.points > 0;
  std::string worse;
  if (b.computed && positions) {
    if (r.position_after.rms > kWorseThanBaseline * b.position.rms)
      worse = fmt("%.4g", r.position_after.rms) + " mm RMS against " + fmt("%.4g", b.position.rms) +
              " mm";
  } else if (b.computed) {
    for (const auto& [unit, rms] : r.residual_rms)
      if (b.residual_rms.count(unit) && rms > kWorseThanBaseline * b.residual_rms.at(unit))
        worse = fmt("%.4g", rms) + " " + unit + " RMS against " +
                fmt("%.4g", b.residual_rms.at(unit)) + " " + unit;
  }
  if (!worse.empty())
    out.push_back({"baseline", L::kDoNotLoad,
                   "The calibration fits the data worse than fitting only the frames "
                   "(registration only): " +
                       worse +
                       ". With the frames among its parameters it can only do better at its "
                       "minimum: the solver stopped in a worse one, or the readings hold "
                       "something the model reads wrongly (e.g. an orientation convention).",
                   "Calibrate from the registration-only result's frames, with --starts, and "
                   "check the readings' conventions."});
  const auto& cv = r.cross_validation;
  if (cv.folds > 0 && cv.position.points > 0 && cv.registration_position.points > 0 &&
      cv.position.rms > kWorseThanBaseline * cv.registration_position.rms)
    out.push_back({"baseline", L::kDoNotLoad,
                   "Held out (" + std::to_string(cv.folds) +
                       "-fold cross-validation), the calibration predicts worse than "
                       "registration only: " +
                       fmt("%.4g", cv.position.rms) + " mm RMS against " +
                       fmt("%.4g", cv.registration_position.rms) +
                       " mm. It fits the calibration data's noise, not the machine.",
                   "Free fewer parameters, add what you know as prior_std, or measure more "
                   "configurations (kincal design)."});
}

void accuracy_findings(const CalibrationReport& r, std::vector<Finding>& out) {
  if (r.position_after.points > 0 && r.position_before.points > 0) {
    if (!(r.position_after.mean < r.position_before.mean))
      out.push_back({"accuracy", L::kDoNotLoad,
                     "The calibration does not reduce the 3-D position error of the measured "
                     "point: " +
                         fmt("%.4g", r.position_before.mean) + " mm mean before, " +
                         fmt("%.4g", r.position_after.mean) + " mm after.",
                     "Check the data, the free parameters and the model."});
    return;
  }
  const AccuracyComparison& a = r.predicted_accuracy;
  // A prediction from the covariance and the stated tolerances, not a measured failure: a
  // warning (exit 0). The same prediction against a --target the user gave is do-not-load.
  // The readings measure no point (a camera's pixels, a gauge's lengths): a fit that lowers
  // their residuals can still move the geometry away from the machine's (issue 38: a camera
  // fit that took a dual-arm robot from 0.25 to 2 mm held out), so this is said in so many
  // words.
  if (r.position_after.points == 0 && a.computed && !a.expected_to_beat_nominal)
    out.push_back({"accuracy", L::kWarning,
                   "This calibration is not expected to beat the nominal model: predicted "
                   "position error " +
                       fmt("%.3g", a.calibrated.position_rms) + " mm RMS against " +
                       fmt("%.3g", a.nominal.position_rms) +
                       " mm for the nominal model. It fits the readings better (cost " +
                       fmt("%.4g", r.summary.initial_cost) + " -> " +
                       fmt("%.4g", r.summary.final_cost) +
                       ") but is not expected to improve the machine.",
                   "Measure configurations chosen by kincal design, add what you know as "
                   "prior_std, or fix the weakly determined parameters."});
}

void data_findings(const CalibrationReport& r, std::vector<Finding>& out) {
  if (r.duplicate_rows > 0)
    out.push_back({"data", L::kNote,
                   std::to_string(r.duplicate_rows) +
                       " row(s) repeat an earlier row exactly, readings included: a copy is "
                       "not a second measurement, so each was counted once.",
                   ""});
  if (r.repeated_configurations > 0)
    out.push_back(
        {"data", L::kNote,
         std::to_string(r.repeated_configurations) +
             " configuration(s) were measured more "
             "than once (" +
             std::to_string(r.repeat_rows) +
             " rows in all): repeats, whose scatter is the noise; the standard deviations "
             "take them as independent measurements of those configurations, so they say "
             "nothing about the configurations that were not measured.",
         ""});
  for (const auto& w : r.warnings) out.push_back({"data", L::kWarning, w, ""});
}

}  // namespace

const char* to_string(Finding::Level level) {
  switch (level) {
    case L::kGood:
      return "good";
    case L::kNote:
      return "note";
    case L::kWarning:
      return "warning";
    case L::kDoNotLoad:
      return "do_not_load";
  }
  return "note";
}

Finding::Level CalibrationVerdict::worst() const {
  Finding::Level worst = L::kGood;
  for (const auto& f : findings) worst = std::max(worst, f.level);
  return worst;
}

std::string CalibrationVerdict::overall() const {
  switch (worst()) {
    case L::kDoNotLoad:
      return "do_not_load";
    case L::kWarning:
      return "check";
    default:
      return "load";
  }
}

CalibrationVerdict judge_calibration(const CalibrationReport& r) {
  CalibrationVerdict v;
  // The most basic first: the first do-not-load finding is the one the command line names.
  solver_finding(r, v.findings);
  fit_findings(r, v.findings);
  baseline_findings(r, v.findings);
  branch_findings(r, v.findings);
  tolerance_finding(r, v.findings);
  accuracy_findings(r, v.findings);
  data_findings(r, v.findings);
  return v;
}

nlohmann::ordered_json to_json(const CalibrationVerdict& v) {
  nlohmann::ordered_json findings = nlohmann::ordered_json::array();
  for (const auto& f : v.findings)
    findings.push_back(
        {{"id", f.id}, {"level", to_string(f.level)}, {"text", f.text}, {"advice", f.advice}});
  return {{"overall", v.overall()}, {"findings", findings}};
}

std::string to_text(const CalibrationVerdict& v) {
  std::ostringstream out;
  const std::string overall = v.overall();
  out << "verdict: "
      << (overall == "load"    ? "load it"
          : overall == "check" ? "check the warnings before loading it"
                               : "do not load it")
      << "\n";
  for (const auto& f : v.findings) {
    if (f.level == L::kGood) continue;
    out << "  " << (f.level == L::kDoNotLoad ? "do not load" : to_string(f.level)) << ": " << f.text
        << "\n";
    if (!f.advice.empty()) out << "    what to do: " << f.advice << "\n";
  }
  return out.str();
}

}  // namespace kincal
