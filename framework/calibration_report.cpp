#include "kincal/framework/calibration_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "kincal/framework/constrained_problem.hpp"
#include "kincal/framework/message_excerpt.hpp"
#include "kincal/framework/units.hpp"
#include "kincal/framework/validation.hpp"

namespace kincal {

namespace {

using Json = nlohmann::ordered_json;

// JSON has no NaN or infinity: such values are written as null.
Json number(double v) { return std::isfinite(v) ? Json(v) : Json(); }

Json numbers(const VectorXd& v) {
  Json out = Json::array();
  for (int i = 0; i < v.size(); ++i) out.push_back(number(v[i]));
  return out;
}

std::string format(const char* fmt, double a) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, a);
  return buf;
}

// What sigma_hat is measured in: the readings' unit, or multiples of the stated reading std.
std::string sigma_unit(const CalibrationReport& r) {
  if (r.weighted) return "reading_std";
  if (r.residual_rms.size() == 1) return r.residual_rms.begin()->first;
  return "mixed";
}

// What a flag means, in words, for the report.
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

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  const auto mid = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

}  // namespace

double normal_two_sided_quantile(double p) {
  if (!(p > 0 && p < 1)) return std::numeric_limits<double>::quiet_NaN();
  // erfc(z / sqrt 2) = P(|Z| > z) falls monotonically: bisection to the last bit.
  double lo = 0, hi = 40;
  for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

CalibrationReport make_calibration_report(const CalibrationProblem& problem, const VectorXd& x,
                                          const Summary& summary, const std::vector<int>& lines,
                                          const RobustLoss& loss,
                                          const IdentifiabilityOptions& options,
                                          const VectorXd& prior_precision) {
  CalibrationReport r;
  r.prior = prior_precision.size() > 0 && (prior_precision.array() > 0).any();
  const MeasurementModel& model = problem.model();
  r.summary = summary;
  r.loss = loss.to_string();
  r.names = problem.parameter_names();
  for (int i : problem.free_indices()) r.units.push_back(model.parameters()[i].unit);
  r.nominal = problem.initial_free_parameters();
  r.estimate = x;
  for (std::size_t i = 0; i < r.units.size(); ++i)
    if (r.units[i] == kRadian) r.estimate[static_cast<int>(i)] = wrap_angle(x[static_cast<int>(i)]);
  r.num_configurations = problem.num_residual_blocks();
  r.reading_names = model.reading_names();
  r.reading_units = model.reading_units();
  r.weighted = model.weighted();
  r.reading_std = model.reading_std();
  r.lines = lines;
  const Measurements& data = problem.data();
  const Eigen::VectorXi present = data.present_per_column();
  for (std::size_t s = 0; s < model.sensors().size(); ++s) {
    const int o = model.sensor_reading_offset(static_cast<int>(s));
    // A sensor's readings are present or missing together: its first column counts them.
    r.readings_per_sensor.push_back({model.sensors()[s]->name(), present[o]});
  }
  r.num_readings = present.sum();
  VectorXd residuals;
  MatrixXd J;
  if (!problem.evaluate(x, &residuals, &J)) return r;

  // Only measured readings count: a missing one is a fixed zero row of J and r, which would
  // add degrees of freedom and residuals that were never observed.
  const int k = problem.residuals_per_block();
  const MatrixXd whitened =
      Eigen::Map<const MatrixXd>(residuals.data(), k, r.num_configurations).transpose();
  std::vector<int> rows;
  for (int c = 0; c < r.num_configurations; ++c)
    for (int i = 0; i < k; ++i)
      if (!std::isnan(data.readings(c, i))) rows.push_back(c * k + i);
  VectorXd measured_r(rows.size());
  MatrixXd measured_J(rows.size(), J.cols());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    measured_r[static_cast<int>(i)] = residuals[rows[i]];
    measured_J.row(static_cast<int>(i)) = J.row(rows[i]);
  }

  r.residuals.resize(r.num_configurations, k);
  std::map<std::string, int> count;
  std::map<std::string, std::vector<double>> magnitudes;  // |whitened residual| per unit
  for (int c = 0; c < r.num_configurations; ++c)
    for (int i = 0; i < k; ++i) {
      if (std::isnan(data.readings(c, i))) {
        r.residuals(c, i) = NAN;
        continue;
      }
      const double value = whitened(c, i) * model.reading_std()[i];
      r.residuals(c, i) = value;
      const std::string& unit = r.reading_units[i];
      r.residual_rms[unit] += value * value;
      r.residual_max[unit] = std::max(r.residual_max[unit], std::abs(value));
      ++count[unit];
      magnitudes[unit].push_back(std::abs(whitened(c, i)));
    }
  for (auto& [unit, sum] : r.residual_rms) sum = std::sqrt(sum / count[unit]);
  // Outliers: beyond the Bonferroni quantile of a robust noise std, per unit (see the header).
  r.outlier_z = normal_two_sided_quantile(kOutlierFamilyProbability /
                                          std::max(1.0, static_cast<double>(r.num_readings)));
  for (const auto& [unit, values] : magnitudes) {
    r.outlier_threshold_by_unit[unit] = std::max(r.outlier_z * 1.4826 * median(values), 1e-9);
  }
  if (!r.reading_units.empty() && r.outlier_threshold_by_unit.count(r.reading_units[0]))
    r.outlier_threshold = r.outlier_threshold_by_unit[r.reading_units[0]];
  double inlier_sum = 0;
  for (int c = 0; c < r.num_configurations; ++c) {
    bool outlier = false;
    for (int i = 0; i < k; ++i)
      outlier =
          outlier || (!std::isnan(data.readings(c, i)) &&
                      std::abs(whitened(c, i)) > r.outlier_threshold_by_unit[r.reading_units[i]]);
    r.outlier.push_back(outlier);
    if (outlier) continue;
    for (int i = 0; i < k; ++i)
      if (!std::isnan(data.readings(c, i))) {
        inlier_sum += whitened(c, i) * whitened(c, i);
        ++r.inlier_readings;
      }
  }

  // Constraints are measurements of the parameters: rows of their own, once.
  append_constraint_rows(problem, x, measured_J, &measured_r);
  if (!model.constraints().empty()) {
    VectorXd whitened_constraints;
    constraint_residuals(problem, x, whitened_constraints, nullptr);
    int row = 0;
    for (const auto& c : model.constraints()) {
      const VectorXd std = c->residual_std();
      const std::vector<std::string> units = c->residual_units();
      for (int i = 0; i < c->num_residuals(); ++i, ++row)
        r.constraints.push_back(
            {c->type(), c->label(), units[i], whitened_constraints[row] * std[i], std[i]});
    }
  }
  r.identifiability = analyze_identifiability(measured_J, r.names, options);
  if (r.prior) {
    r.uncertainty = estimate_posterior_uncertainty(measured_J, measured_r, prior_precision, loss);
    add_prior(r.identifiability, measured_J, prior_precision, r.uncertainty.data_share, options);
    // As the user gave them (1 / sqrt(precision) would round).
    for (std::size_t i = 0; i < problem.free_indices().size(); ++i)
      if (r.uncertainty.prior_std[static_cast<int>(i)] > 0)
        r.uncertainty.prior_std[static_cast<int>(i)] =
            model.parameters()[problem.free_indices()[i]].prior_std;
  } else {
    r.uncertainty = estimate_uncertainty(measured_J, measured_r, loss);
    if (loss.kind != RobustLoss::Kind::kNone) {
      // The noise a held-out reading shows is that of the unweighted residuals of the
      // inliers; the down-weighted ones (psi) would understate it.
      r.psi_sigma = r.uncertainty.sigma;
      const int dof = r.inlier_readings - static_cast<int>(r.names.size());
      r.uncertainty.sigma = dof > 0 ? std::sqrt(inlier_sum / dof) : NAN;
    }
  }
  r.fit_check = check_fit(r, measured_r);
  r.predicted_accuracy = compare_with_nominal(model, problem.full_parameters(x),
                                              problem.free_indices(), r.uncertainty.covariance);
  r.pose_accuracy_shown = measures_position(model);
  if (r.pose_accuracy_shown) {
    try {
      r.position_before = summarize_position_errors(
          position_errors(model, residual_matrix(problem, problem.initial_free_parameters())));
    } catch (const std::runtime_error&) {
      // The starting values cannot reach some configuration: no "before" figure.
    }
    r.position_after = summarize_position_errors(position_errors(model, r.residuals));
    r.predicted_point = predict_point_errors(problem, x, r.uncertainty.covariance);
  }
  return r;
}

FitCheck check_fit(const CalibrationReport& r, const VectorXd& measured_whitened) {
  FitCheck f;
  if (!r.weighted)
    f.not_tested = kFitNoNoise;
  else if (r.prior)
    f.not_tested = "a MAP fit: the prior pulls the residuals away from the data's minimum";
  else if (r.loss != "none")
    f.not_tested = "a robust loss: the residuals of outliers do not follow the noise";
  else if (r.uncertainty.degrees_of_freedom <= 0)
    f.not_tested = "no degrees of freedom (as many readings as parameters)";
  if (!f.not_tested.empty()) return f;
  f.tested = true;
  f.chi_square = measured_whitened.squaredNorm();
  f.degrees_of_freedom = r.uncertainty.degrees_of_freedom;
  f.p_larger = chi_square_upper_tail(f.chi_square, f.degrees_of_freedom);
  return f;
}

Json to_json(const Identifiability& a) {
  Json out;
  out["residuals"] = a.num_residuals;
  out["parameters"] = a.num_parameters;
  out["scaling"] = "columns of J scaled to unit norm";
  out["singular_values"] = numbers(a.singular_values);
  out["rank"] = a.rank;
  out["rank_threshold"] = a.rank_threshold;
  out["numerical_rank"] = a.numerical_rank;
  out["numerical_rank_threshold"] = a.numerical_threshold;
  out["rcond"] = a.rcond;
  out["condition_number"] = number(a.condition_number);
  out["O1"] = a.o1;
  out["O2"] = a.o2;
  out["O3"] = a.o3;
  out["O4"] = a.o4;
  out["O5"] = a.o5;
  out["unseen_parameters"] = a.unseen;
  if (a.has_prior()) {
    out["numerical_rank_with_prior"] = a.numerical_rank_with_prior;
    Json shares = Json::array();
    for (int i = 0; i < a.data_share.size(); ++i)
      shares.push_back({{"name", a.names[i]},
                        {"data_share", a.data_share[i]},
                        {"prior_share", 1 - a.data_share[i]}});
    out["data_share"] = shares;
  }
  out["combinations"] = Json::array();
  for (const auto& c : a.combinations) {
    Json terms = Json::array();
    for (const auto& [name, coefficient] : c.terms)
      terms.push_back({{"name", name}, {"coefficient", coefficient}});
    Json combination = {{"singular_value", c.singular_value},
                        {"kind", c.null_space ? "null_space" : "weak"},
                        {"terms", terms}};
    if (a.has_prior()) combination["determined_by_prior"] = !a.undetermined();
    out["combinations"].push_back(combination);
  }
  return out;
}

Json to_json(const CalibrationReport& r) {
  Json out;
  out["format"] = "kincal-calibration-report";
  out["version"] = 1;
  out["model"] = r.model_file;
  out["data"] = r.data_file;
  out["solver"] = r.summary.solver;
  out["formulation"] = r.formulation;
  out["loss"] = r.loss;
  out["termination"] = to_string(r.summary.termination);
  out["message"] = r.summary.message;
  out["iterations"] = r.summary.iterations;
  out["initial_cost"] = number(r.summary.initial_cost);
  out["final_cost"] = number(r.summary.final_cost);
  out["configurations"] = r.num_configurations;
  out["readings"] = r.num_readings;
  Json per_sensor = Json::object();
  for (const auto& [name, count] : r.readings_per_sensor) per_sensor[name] = count;
  out["readings_per_sensor"] = per_sensor;
  out["skipped_lines"] = r.skipped_lines;
  out["dropped_readings"] = r.dropped_readings;
  // One unit: plain numbers, as always; several: the pooled figure would mix mm and rad.
  const bool one_unit = r.residual_rms.size() == 1;
  out["residual_rms"] = one_unit ? Json(r.residual_rms.begin()->second) : Json();
  out["residual_max"] = one_unit ? Json(r.residual_max.begin()->second) : Json();
  out["residual_rms_by_unit"] = r.residual_rms;
  out["residual_max_by_unit"] = r.residual_max;
  out["weighted"] = r.weighted;
  Json reading_units = Json::object(), reading_std = Json::object();
  for (std::size_t k = 0; k < r.reading_names.size(); ++k) {
    reading_units[r.reading_names[k]] = r.reading_units[k];
    reading_std[r.reading_names[k]] =
        r.weighted && r.reading_std.size() ? number(r.reading_std[static_cast<int>(k)]) : Json();
  }
  out["reading_units"] = reading_units;
  out["reading_std"] = reading_std;  // null: not stated by the model
  out["sigma_hat"] = number(r.uncertainty.sigma);
  out["sigma_hat_unit"] = sigma_unit(r);
  out["sigma_hat_from"] = r.loss == "none" || r.prior
                              ? "residuals"
                              : "unweighted residuals of the configurations not flagged as "
                                "outliers";
  if (r.loss != "none") out["sigma_psi"] = number(r.psi_sigma);
  out["degrees_of_freedom"] = r.uncertainty.degrees_of_freedom;
  {
    const FitCheck& f = r.fit_check;
    Json fit;
    fit["verdict"] = !f.tested ? "not_tested" : f.too_large() ? "too_large" : "consistent";
    fit["chi_square"] = f.tested ? number(f.chi_square) : Json();
    fit["degrees_of_freedom"] = f.tested ? Json(f.degrees_of_freedom) : Json();
    fit["p_larger"] = f.tested ? number(f.p_larger) : Json();
    fit["note"] = !f.tested       ? f.not_tested
                  : f.too_large() ? std::string(kFitTooLarge)
                                  : std::string(kFitConsistent);
    out["fit_check"] = fit;
  }
  out["effective_degrees_of_freedom"] = number(r.uncertainty.effective_degrees_of_freedom);
  out["robust_std_factor"] = number(r.uncertainty.robust_factor);
  out["prior"] = r.prior;
  out["parameters"] = Json::array();
  for (std::size_t i = 0; i < r.names.size(); ++i) {
    const double std = r.uncertainty.std.size() ? r.uncertainty.std[i] : NAN;
    const bool has_prior = r.uncertainty.prior_std.size() && r.uncertainty.prior_std[i] > 0;
    const double share = r.uncertainty.data_share.size() ? r.uncertainty.data_share[i] : 1.0;
    out["parameters"].push_back(
        {{"name", r.names[i]},
         {"unit", r.units[i]},
         {"nominal", r.nominal[i]},
         {"estimate", r.estimate[i]},
         {"std", number(std)},
         {"prior_std", has_prior ? Json(r.uncertainty.prior_std[i]) : Json()},
         {"data_share", r.uncertainty.std.size() ? Json(share) : Json()}});
  }
  out["fixed_by_identifiability"] = r.fixed_by_identifiability;
  if (!r.constraints.empty()) {
    out["constraints"] = Json::array();
    for (const auto& c : r.constraints)
      out["constraints"].push_back({{"type", c.type},
                                    {"label", c.label},
                                    {"residual", number(c.residual)},
                                    {"std", c.std},
                                    {"unit", c.unit}});
  }
  Json correlation = Json::array();
  for (int i = 0; i < r.uncertainty.correlation.rows(); ++i)
    correlation.push_back(numbers(r.uncertainty.correlation.row(i).transpose()));
  out["correlation"] = correlation;
  out["outlier_threshold"] = r.outlier_threshold;
  out["outlier_threshold_by_unit"] = r.outlier_threshold_by_unit;
  out["outlier_z"] = number(r.outlier_z);
  out["outlier_family_probability"] = kOutlierFamilyProbability;
  out["outlier_meaning"] = outlier_meaning(r);
  out["residuals"] = Json::array();
  for (int c = 0; c < r.residuals.rows(); ++c) {
    Json row;
    row["line"] = r.lines[c];
    for (int k = 0; k < r.residuals.cols(); ++k)
      row[r.reading_names[k]] = number(r.residuals(c, k));  // null: not measured
    row["outlier"] = static_cast<bool>(r.outlier[c]);
    out["residuals"].push_back(row);
  }
  out["identifiability"] = to_json(r.identifiability);
  out["warnings"] = r.warnings;
  out["predicted_pose_error"] = to_json(r.predicted_accuracy);
  out["pose_accuracy_shown"] = r.pose_accuracy_shown;
  out["pose_accuracy_note"] = r.pose_accuracy_shown ? Json() : Json(kPoseAccuracyNotShown);
  if (r.position_after.points > 0) {
    Json position = {{"before", to_json(r.position_before)}, {"after", to_json(r.position_after)}};
    position["before_is"] = "the model's starting values, on the calibration data";
    position["after_is"] = "the estimate, on the calibration data (in-sample)";
    if (r.registration.computed) {
      position["registration_only"] = to_json(r.registration.position);
    }
    out["position_error_mm"] = position;
    Json predicted = to_json(r.predicted_point);
    predicted["where"] =
        "the measured point at the measured configurations, from the covariance of all fitted "
        "parameters";
    predicted["before_measured"] = to_json(r.position_before);
    out["predicted_point_error_mm"] = predicted;
  }
  Json registration = {{"computed", r.registration.computed}};
  if (r.registration.computed) {
    registration["parameters"] = r.registration.names;
    registration["termination"] = r.registration.termination;
    registration["residual_rms_by_unit"] = r.registration.residual_rms;
    if (r.registration.position.points > 0)
      registration["position_error_mm"] = to_json(r.registration.position);
  } else {
    registration["why_not"] = r.registration.why_not;
  }
  out["registration_only"] = registration;
  if (r.cross_validation.folds > 0) {
    const auto& cv = r.cross_validation;
    Json folds = {{"folds", cv.folds},
                  {"assignment", "configuration i (file order) in fold i mod K"},
                  {"failed_folds", cv.failed},
                  {"residual_rms_by_unit", cv.residual_rms},
                  {"registration_only_residual_rms_by_unit", cv.registration_residual_rms}};
    if (cv.failed) folds["failure"] = cv.failure;
    if (cv.position.points > 0) {
      folds["position_error_mm"] = to_json(cv.position);
      folds["registration_only_position_error_mm"] = to_json(cv.registration_position);
    }
    out["cross_validation"] = folds;
  }
  return out;
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
  // Only a flagged fit: the JSON holds the check either way.
  if (r.fit_check.too_large())
    out << "fit check: chi-square " << format("%.4g", r.fit_check.chi_square) << " on "
        << r.fit_check.degrees_of_freedom << " degrees of freedom against the stated noise, "
        << "P(larger) " << format("%.3g", r.fit_check.p_larger) << ": " << kFitTooLarge << "\n";
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
  char buf[200];
  std::snprintf(buf, sizeof buf, "  %-22s %-4s %14s %14s %12s %12s", "name", "unit", "nominal",
                "estimate", "change", "std");
  out << buf << (r.prior ? "    prior std  data %\n" : "\n");
  for (std::size_t i = 0; i < r.names.size(); ++i) {
    const double change = r.units[i] == kRadian ? wrap_angle(r.estimate[i] - r.nominal[i])
                                                : r.estimate[i] - r.nominal[i];
    std::snprintf(buf, sizeof buf, "  %-22s %-4s %14.6f %14.6f %12.6f %12.3g", r.names[i].c_str(),
                  r.units[i].c_str(), r.nominal[i], r.estimate[i], change,
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
  for (const auto& name : r.fixed_by_identifiability)
    out << "  " << name << ": fixed at its model value (not identifiable from this data)\n";
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
      for (const auto& [u, rms] : r.cross_validation.residual_rms)
        out << "held out, " << r.cross_validation.folds << "-fold: residual RMS "
            << format("%.4g", rms) << " " << u << " (registration only "
            << format("%.4g", r.cross_validation.registration_residual_rms.count(u)
                                  ? r.cross_validation.registration_residual_rms.at(u)
                                  : NAN)
            << ")\n";
  }
  // For a point-measuring sensor the measured figures above replace the box prediction (the
  // flange, from assumed tolerances); it stays in the JSON.
  if (r.position_after.points == 0) out << to_text(r.predicted_accuracy);
  if (!r.pose_accuracy_shown) out << "note: " << kPoseAccuracyNotShown << "\n";
  for (const auto& warning : r.warnings) out << "warning: " << warning << "\n";
  return out.str();
}

}  // namespace kincal
