// The calibration report as JSON (calibrate --json): NaN and infinity written as null.
#include "kincal/framework/analysis/calibration_report.hpp"

#include <cmath>

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

}  // namespace

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
  if (a.frame_turns > 0) out["measurement_frame_turns"] = a.frame_turns;
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
  out["formulation_note"] = r.formulation_note;
  out["loss"] = r.loss;
  {
    const SolverOptions& o = r.solver_options;
    // Every backend setting in force, defaults included (calibrate fills o.backend).
    Json backend = Json::object();
    if (o.backend)
      for (const auto& [key, value] : o.backend->in_force()) backend[key] = value;
    out["solver_options"] = {{"max_iterations", o.max_iterations},
                             {"function_tolerance", o.function_tolerance},
                             {"parameter_tolerance", o.parameter_tolerance},
                             {"gradient_tolerance", o.gradient_tolerance},
                             {"num_threads", o.num_threads},
                             {"backend_options", backend}};
  }
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
    // Above the stated noise is not by itself a model error (real set-ups scatter more than
    // their datasheet): the residuals' shape and the verdict say which it is.
    fit["note"] = !f.tested       ? f.not_tested
                  : f.too_large() ? std::string(kFitAboveStatedNoise)
                                  : std::string(kFitConsistent);
    out["fit_check"] = fit;
  }
  {
    const ResidualStructure& s = r.structure;
    Json shape;
    shape["tested"] = s.tested;
    if (!s.tested) shape["why_not"] = s.not_tested;
    shape["neighbour_pairs"] = s.pairs;
    shape["neighbour_fraction"] = number(s.neighbour_fraction);
    shape["neighbour_z"] = number(s.neighbour_z);
    shape["mean_neighbour_distance"] = number(s.mean_neighbour_distance);
    shape["neighbour_structured"] = s.neighbour_structured();
    shape["fixed_directions"] = s.fixed_directions;
    shape["fixed_fraction"] = number(s.fixed_fraction);
    shape["fixed_p"] = number(s.fixed_p);
    shape["dominant_fixed"] = s.dominant_fixed.empty() ? Json() : Json(s.dominant_fixed);
    shape["dominant_fixed_fraction"] = number(s.dominant_fixed_fraction);
    shape["fixed_structured"] = s.fixed_structured();
    Json spread = Json::object();
    for (const auto& [unit, share] : s.unexplained_spread)
      spread[unit] = {{"reading_spread", number(s.reading_spread.at(unit))},
                      {"unexplained_share", number(share)}};
    shape["unexplained_spread"] = spread;
    out["residual_structure"] = shape;
  }
  out["nominal_branch"] = {
      {"mapped", r.branch_mapped},
      {"rejected", r.branch_rejected.empty() ? Json() : Json(r.branch_rejected)},
      {"off_branch", r.off_branch}};
  out["far_corrections"] = Json::array();
  for (const auto& c : r.far_corrections)
    out["far_corrections"].push_back({{"name", c.name},
                                      {"unit", c.unit},
                                      {"change", number(c.change)},
                                      {"tolerance", number(c.tolerance)},
                                      {"tolerance_assumed", c.assumed}});
  out["duplicate_rows"] = r.duplicate_rows;
  out["repeated_configurations"] = r.repeated_configurations;
  out["repeat_rows"] = r.repeat_rows;
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
    if (r.point_located.computed) {
      position["nominal_point_located"] = to_json(r.point_located.position);
      position["nominal_point_located_is"] =
          "the starting values with only the measured point's position on the end effector "
          "fitted (" +
          std::to_string(r.point_located.names.size()) + " parameters)";
    }
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

}  // namespace kincal
