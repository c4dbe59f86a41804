// The calibration report as text, for the terminal (calibrate without --json).
#include "kincal/framework/analysis/calibration_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "kincal/framework/analysis/identifiability_words.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal {

namespace {

std::string format(const char* fmt, double a) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, a);
  return buf;
}

}  // namespace

std::string sigma_unit(const CalibrationReport& r) {
  if (r.weighted) return "reading_std";
  if (r.residual_rms.size() == 1) return r.residual_rms.begin()->first;
  return "mixed";
}

std::string outlier_meaning(const CalibrationReport& r) {
  return "a configuration is flagged when one of its residuals" +
         std::string(r.weighted ? " (divided by its reading_std)" : "") + " exceeds " +
         format("%.3g", r.outlier_z) +
         " robust standard deviations (1.4826 x the median |residual| of its unit): the level "
         "that clean Gaussian noise on all " +
         std::to_string(r.num_readings) + " readings exceeds anywhere with probability " +
         format("%.2g", kOutlierFamilyProbability) +
         " (Bonferroni), so a flag on clean data is rare and a flagged configuration is "
         "worth checking";
}

std::string to_text(const Identifiability& a) {
  std::ostringstream out;
  out << "identifiability (" << a.num_residuals << " residuals, " << a.num_parameters
      << " free parameters, columns scaled to unit norm):\n";
  out << "  rank " << a.rank << " (threshold " << format("%.2e", a.rank_threshold)
      << "), numerical rank " << a.numerical_rank << " (threshold "
      << format("%.2e", a.numerical_threshold) << " = " << format("%g", a.rcond) << " x s_max)\n";
  out << "  singular values " << format("%.4g", a.singular_values.size() ? a.singular_values[0] : 0)
      << " .. "
      << format("%.4g", a.singular_values.size() ? a.singular_values[a.num_parameters - 1] : 0)
      << ", condition number " << format("%.4g", a.condition_number);
  if (std::isinf(a.condition_number) && a.num_parameters > 0)
    out << " (rank deficient: " << std::min(a.rank, a.numerical_rank) << " of " << a.num_parameters
        << " directions determined; singular values below the threshold count as 0, so "
           "O1..O5 are 0)";
  out << "\n";
  out << "  O1 " << format("%.4g", a.o1) << "  O2 " << format("%.4g", a.o2) << "  O3 "
      << format("%.4g", a.o3) << "  O4 " << format("%.4g", a.o4) << "  O5 " << format("%.4g", a.o5)
      << "\n";
  if (a.frame_turns > 0)
    out << "  " << a.frame_turns
        << " turn(s) of the whole setup change no fit (a gauge freedom: nothing measured fixes "
           "the measurement frame's orientation): projected out, each a direction not "
           "determined\n";
  const bool pinned = a.has_prior() && !a.undetermined();
  if (a.has_prior())
    out << "  with the prior: numerical rank " << a.numerical_rank_with_prior << " of "
        << a.num_parameters
        << (pinned ? "" : " (data and prior together cannot determine every parameter)") << "\n";
  for (const auto& name : a.unseen)
    out << "  not seen by the data: " << name << (pinned ? " (determined by its prior)" : "")
        << "\n";
  // The weakest few are what a reader can act on; all of them are in the JSON.
  int shown = 0;
  for (const auto& c : a.combinations)
    if (shown++ < 3)
      out << "  "
          << (c.null_space ? (pinned ? "not seen by the data, determined by the prior"
                                     : "cannot be determined")
                           : "weakly determined by the data")
          << " (s = " << format("%.2e", c.singular_value) << "): " << c.describe() << "\n";
  return out.str();
}

std::string to_text(const CalibrationReport& r) {
  std::ostringstream out;
  out << "calibration of " << printable(r.model_file) << " from " << printable(r.data_file) << ": "
      << r.num_configurations << " configurations";
  if (!r.skipped_lines.empty()) out << " (" << r.skipped_lines.size() << " rows skipped)";
  if (!r.dropped_readings.empty())
    out << " (" << r.dropped_readings.size() << " readings dropped: no reading)";
  out << "\n" << r.summary.brief_report() << "\n";
  {
    const std::vector<std::string> changed = changed_settings(r.solver_options);
    out << "solver settings: ";
    for (std::size_t i = 0; i < changed.size(); ++i) out << (i ? ", " : "") << changed[i];
    out << (changed.empty() ? "the defaults" : "; the others at their defaults")
        << " (the JSON report lists each one)\n";
  }
  out << "readings:";
  for (const auto& [name, count] : r.readings_per_sensor) out << " " << name << " " << count;
  out << " of " << r.num_configurations << " configurations\n";
  for (const auto& [unit, rms] : r.residual_rms)
    out << "residuals (" << unit << "): RMS " << format("%.4g", rms) << ", max "
        << format("%.4g", r.residual_max.at(unit)) << "\n";
  for (const auto& c : r.constraints)
    out << "constraint " << c.type << " " << c.label << ": residual " << format("%+.4g", c.residual)
        << " " << c.unit << " (std " << format("%.4g", c.std) << ")\n";
  const std::string unit = sigma_unit(r);
  out << "sigma_hat " << format("%.4g", r.uncertainty.sigma) << " "
      << (unit == "reading_std" ? "x the stated reading std (1 = as stated)"
          : unit == "mixed"     ? "(mm and rad pooled unweighted: state reading_std in the "
                                  "model file to weigh them)"
                                : unit)
      << " (";
  if (r.prior)
    out << format("%.1f", r.uncertainty.effective_degrees_of_freedom)
        << " effective degrees of freedom: readings less the parameters the data determine";
  else
    out << r.uncertainty.degrees_of_freedom << " degrees of freedom";
  if (r.loss != "none")
    out << "; from the unweighted residuals of the " << r.inlier_readings
        << " readings not flagged as outliers; the standard deviations use the residuals as the "
        << r.loss << " loss sees them (" << format("%.4g", r.psi_sigma)
        << ") scaled by Huber's factor " << format("%.3g", r.uncertainty.robust_factor);
  out << ")\n";
  // Above the stated noise: the verdict says whether that is noise or a model error.
  if (r.fit_check.too_large())
    out << "fit check: chi-square " << format("%.4g", r.fit_check.chi_square) << " on "
        << r.fit_check.degrees_of_freedom << " degrees of freedom against the stated noise, "
        << "P(larger) " << format("%.3g", r.fit_check.p_larger) << ": above the stated noise\n";
  if (r.structure.tested)
    out << "residual shape: " << format("%.0f", 100 * std::max(0.0, r.structure.neighbour_fraction))
        << " % of the variance shared by neighbouring configurations"
        << (r.structure.fixed_directions > 0
                ? ", " + format("%.0f", 100 * r.structure.fixed_fraction) +
                      " % explained by the fixed parameters' " +
                      std::to_string(r.structure.fixed_directions) + " directions (noise: P " +
                      format("%.2g", r.structure.fixed_p) + ")"
                : std::string())
        << "\n";
  if (r.loss != "none" && std::isnan(r.uncertainty.robust_factor))
    out << "no standard deviations: the " << r.loss
        << " loss rejects most residuals (its delta is too small for this data)\n";
  int outliers = 0;
  for (bool o : r.outlier) outliers += o;
  if (outliers) {
    out << outliers << " outlier configuration(s) (|residual|" << (r.weighted ? " / std" : "")
        << " >";
    for (const auto& [u, threshold] : r.outlier_threshold_by_unit)
      out << " " << format("%.3g", threshold) << (r.weighted ? "" : " " + u);
    out << ", " << format("%.3g", r.outlier_z) << " robust std) at line(s)";
    for (std::size_t c = 0; c < r.outlier.size(); ++c)
      if (r.outlier[c]) out << " " << r.lines[c];
    out << "\n  (" << outlier_meaning(r) << ")\n";
  }
  if (r.prior)
    out << "MAP estimate with a Gaussian prior around the model's values: std is the "
           "posterior std; data % = the share of each parameter the data determine (1 - "
           "posterior var / prior var), the rest is the prior's\n";
  out << "parameters:\n";
  // The name column as wide as the longest name (an imported arm's reach 29 characters).
  int name_width = 22;
  for (const std::string& name : r.names)
    name_width = std::max(name_width, static_cast<int>(std::min<std::size_t>(name.size(), 128)));
  char buf[400];
  std::snprintf(buf, sizeof buf, "  %-*s %-4s %14s %14s %12s %12s", name_width, "name", "unit",
                "nominal", "estimate", "change", "std");
  out << buf << (r.prior ? "    prior std  data %\n" : "\n");
  for (std::size_t i = 0; i < r.names.size(); ++i) {
    const double change = r.units[i] == kRadian ? wrap_angle(r.estimate[i] - r.nominal[i])
                                                : r.estimate[i] - r.nominal[i];
    std::snprintf(buf, sizeof buf, "  %-*s %-4s %14.6f %14.6f %12.6f %12.3g", name_width,
                  r.names[i].c_str(), r.units[i].c_str(), r.nominal[i], r.estimate[i], change,
                  r.uncertainty.std.size() ? r.uncertainty.std[i] : NAN);
    out << buf;
    if (r.prior && r.uncertainty.data_share.size()) {
      const double prior_std = r.uncertainty.prior_std[i];
      if (prior_std > 0)
        std::snprintf(buf, sizeof buf, " %12.3g %6.1f\n", prior_std,
                      100 * r.uncertainty.data_share[i]);
      else
        std::snprintf(buf, sizeof buf, " %12s %6.1f\n", "-", 100.0);
      out << buf;
    } else {
      out << "\n";
    }
  }
  if (!r.fixed_by_identifiability.empty())
    out << fixed_parameters_table(r.fixed_by_identifiability, r.fixed_effects);
  // The strongest correlations are what a reader acts on; the matrix is in the JSON.
  double worst = 0;
  int wi = -1, wj = -1;
  for (int i = 0; i < r.uncertainty.correlation.rows(); ++i)
    for (int j = 0; j < i; ++j)
      if (std::abs(r.uncertainty.correlation(i, j)) > worst) {
        worst = std::abs(r.uncertainty.correlation(i, j));
        wi = i;
        wj = j;
      }
  if (wi >= 0)
    out << "largest correlation " << format("%+.3f", r.uncertainty.correlation(wi, wj))
        << " between " << r.names[wi] << " and " << r.names[wj] << "\n";
  out << to_text(r.identifiability);
  if (r.position_after.points > 0) {
    const auto line = [&](const std::string& label, const PositionErrorStats& p) {
      std::snprintf(buf, sizeof buf, "  %-44s mean %9.4g  RMS %9.4g  max %9.4g\n", label.c_str(),
                    p.mean, p.rms, p.max);
      out << buf;
    };
    out << "3-D position error of the measured point, mm (" << r.position_after.points
        << " points):\n";
    line("before (the starting values)", r.position_before);
    if (r.point_located.computed && r.point_located.position.points > 0)
      line("nominal, point located (" + std::to_string(r.point_located.names.size()) +
               " parameters)",
           r.point_located.position);
    if (r.registration.computed && r.registration.position.points > 0)
      line("registration only (" + std::to_string(r.registration.names.size()) +
               " frame parameters)",
           r.registration.position);
    line("calibrated (" + std::to_string(r.names.size()) + " parameters)", r.position_after);
    if (r.cross_validation.folds > 0 && r.cross_validation.position.points > 0) {
      line("held out, " + std::to_string(r.cross_validation.folds) + "-fold: registration only",
           r.cross_validation.registration_position);
      line("held out, " + std::to_string(r.cross_validation.folds) + "-fold: calibrated",
           r.cross_validation.position);
    }
    if (r.cross_validation.failed)
      out << "  (" << r.cross_validation.failed
          << " fold fit(s) failed: " << r.cross_validation.failure << ")\n";
    if (r.predicted_point.points > 0)
      out << "predicted error of the measured point at the measured configurations from the "
             "parameters' uncertainty: 1 sigma mean "
          << format("%.4g", r.predicted_point.mean_1sigma) << " / max "
          << format("%.4g", r.predicted_point.max_1sigma) << " mm (95 %: mean "
          << format("%.4g", r.predicted_point.mean_95) << " / max "
          << format("%.4g", r.predicted_point.max_95) << " mm); before calibration measured "
          << format("%.4g", r.position_before.mean) << " mm mean\n";
  } else {
    if (r.registration.computed)
      for (const auto& [u, rms] : r.registration.residual_rms)
        out << "registration only (" << r.registration.names.size()
            << " frame parameters): residual RMS " << format("%.4g", rms) << " " << u << "\n";
    if (r.cross_validation.folds > 0)
      for (const auto& [u, rms] : r.cross_validation.residual_rms) {
        // A mechanism without frame parameters (a hexapod measured by a gauge) has no
        // registration-only fit to compare with.
        const auto registration = r.cross_validation.registration_residual_rms.find(u);
        out << "held out, " << r.cross_validation.folds << "-fold: residual RMS "
            << format("%.4g", rms) << " " << u;
        if (registration != r.cross_validation.registration_residual_rms.end())
          out << " (registration only " << format("%.4g", registration->second) << ")";
        out << "\n";
      }
  }
  // For a point-measuring sensor the measured figures above replace the box prediction (the
  // flange, from assumed tolerances); it stays in the JSON.
  if (r.position_after.points == 0) out << to_text(r.predicted_accuracy);
  if (!r.pose_accuracy_shown) out << "note: " << kPoseAccuracyNotShown << "\n";
  for (const auto& warning : r.warnings) out << "warning: " << warning << "\n";
  return out.str();
}

}  // namespace kincal
