// What a calibration reports, computed: the fit, the estimates with their uncertainty, the
// per-configuration residuals with outlier flags, identifiability and the fit check. Written
// out by calibration_report_json.cpp and calibration_report_text.cpp.
#include "kincal/framework/analysis/calibration_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/base/statistics.hpp"
#include "kincal/framework/calibration/constrained_problem.hpp"
#include "kincal/framework/calibration/equivalent_solutions.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal {

namespace {

// The middle element (the upper one of an even count, no interpolation): the robust scale of
// the outlier flags has always used it, unlike base/statistics.hpp's interpolating median.
double upper_median(std::vector<double> values) {
  if (values.empty()) return 0;
  const auto mid = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

// What is far from nominal after the branch map: angles on another branch, corrections far
// beyond their tolerance; outside the registration frames, whose starting values are guesses.
void add_branch_and_tolerances(CalibrationReport& r, const CalibrationProblem& problem,
                               const VectorXd& x) {
  const MeasurementModel& model = problem.model();
  std::vector<bool> assumed;
  const VectorXd tolerance = parameter_tolerances(model, &assumed);
  const std::vector<int> frames = registration_indices(model, problem.free_indices());
  const VectorXd full = problem.full_parameters(x);
  const VectorXd nominal = problem.full_parameters(problem.initial_free_parameters());
  char text[200];
  for (int i : problem.free_indices()) {
    if (std::find(frames.begin(), frames.end(), i) != frames.end()) continue;
    const Parameter& p = model.parameters()[i];
    const bool angle = p.unit == kRadian;
    const double change = angle ? wrap_angle(full[i] - nominal[i]) : full[i] - nominal[i];
    if (angle && std::abs(change) > kPi / 2) {
      std::snprintf(text, sizeof text, "%s %.6g rad (nominal %.6g)", p.name.c_str(),
                    nominal[i] + change, nominal[i]);
      r.off_branch.push_back(text);
    }
    if (std::abs(change) > kFarBeyondTolerance * tolerance[i])
      r.far_corrections.push_back({p.name, p.unit, change, tolerance[i], assumed[i]});
  }
  std::sort(r.far_corrections.begin(), r.far_corrections.end(), [](const auto& a, const auto& b) {
    return std::abs(a.change) / a.tolerance > std::abs(b.change) / b.tolerance;
  });
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
    if (r.units[i] == kRadian)  // on the branch nearest the nominal value
      r.estimate[static_cast<int>(i)] =
          r.nominal[static_cast<int>(i)] +
          wrap_angle(x[static_cast<int>(i)] - r.nominal[static_cast<int>(i)]);
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
    const int k = model.sensors()[s]->num_readings();
    // The configurations in which the sensor took any reading (a camera's points are missing
    // one by one).
    int rows = 0;
    for (int c = 0; c < data.size(); ++c)
      rows += !data.readings.row(c).segment(o, k).array().isNaN().all();
    r.readings_per_sensor.push_back({model.sensors()[s]->name(), rows});
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
  const std::vector<int> rows = data.present_rows();
  VectorXd measured_r = residuals(rows);
  MatrixXd measured_J = J(rows, Eigen::all);

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
    r.outlier_threshold_by_unit[unit] = std::max(r.outlier_z * 1.4826 * upper_median(values), 1e-9);
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
  r.structure = analyze_residual_structure(problem, x);
  add_branch_and_tolerances(r, problem, x);
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

}  // namespace kincal
