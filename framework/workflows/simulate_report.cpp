#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

#include "kincal/framework/analysis/starts_report.hpp"
#include "kincal/framework/base/format_text.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/calibration/fit_check.hpp"
#include "kincal/framework/calibration/measurement_file.hpp"
#include "kincal/framework/io/sha256.hpp"
#include "kincal/framework/kinematics/pose.hpp"
#include "kincal/framework/kinematics/units.hpp"
#include "kincal/framework/workflows/simulate.hpp"

namespace kincal {

namespace {

void print_errors(std::string& text, const char* label, const PoseErrorStats& e) {
  text += format_text(
      "  %-8s position mean %10.6f mm  max %10.6f mm   orientation mean %.3e rad  max %.3e rad",
      label, e.position_mean_mm, e.position_max_mm, e.orientation_mean_rad, e.orientation_max_rad);
  if (e.fk_failures) text += format_text("  (%d poses unreachable)", e.fk_failures);
  text += format_text("\n");
}

// "±5 mm, ±0.01 rad" for the units the free parameters (or readings) are in.
std::string per_unit(const UnitValues& values, const std::set<std::string>& units) {
  std::string out;
  for (const std::string& unit : units)
    out += format_text("%s±%g %s", out.empty() ? "" : ", ", values.get(unit, 0), unit.c_str());
  return out;
}

void print_report(std::string& text, const Scenario& scenario, const CalibrationRun& run,
                  int case_id, const std::string& model_name) {
  const ScenarioOptions& o = scenario.options;
  const Summary& s = run.summary;
  const MeasurementModel& model = *scenario.model;
  // The units whose errors the option gives, and how many parameters the model gives their
  // own (param_error: a camera preset's px and distortion errors).
  std::set<std::string> parameter_units, reading_units;
  int own_errors = 0;
  for (int i : scenario.free_indices) {
    const Parameter& p = model.parameters()[i];
    if (std::isnan(p.error_half_width))
      parameter_units.insert(p.unit);
    else
      ++own_errors;
  }
  std::string parameter_errors = per_unit(o.param_error_half_width, parameter_units);
  if (own_errors > 0)
    parameter_errors +=
        format_text("%s%d parameter%s the model's own (param_error)",
                    parameter_errors.empty() ? "" : ", ", own_errors, own_errors == 1 ? "" : "s");
  for (const auto& u : model.reading_units()) reading_units.insert(u);
  text += format_text("kincal simulate: %s, ", model_name.c_str());
  if (case_id) text += format_text("case %d, ", case_id);
  text += format_text("%d configurations, reading noise %s, %s, seed %llu\n", o.num_configurations,
                      per_unit(o.noise_half_width, reading_units).c_str(),
                      o.truth.size() ? "true model given (--truth)"
                                     : ("parameter errors " + parameter_errors).c_str(),
                      static_cast<unsigned long long>(o.seed));
  if (o.prior_std.any_positive()) {
    std::string stds;
    for (const auto& [unit, value] : o.prior_std.values())
      if (value > 0) stds += format_text("%s%g %s", stds.empty() ? "" : ", ", value, unit.c_str());
    text += format_text(
        "MAP estimate: Gaussian prior of std %s around nominal on every free parameter\n",
        stds.c_str());
  } else {
    int with_prior = 0;
    for (int i : scenario.free_indices) with_prior += model.parameters()[i].has_prior();
    if (with_prior)
      text +=
          format_text("MAP estimate: Gaussian prior around nominal on %d of %zu free parameters\n",
                      with_prior, scenario.free_indices.size());
  }
  text += format_text("solver %s: %s — %s\n", s.solver.c_str(), to_string(s.termination),
                      s.message.c_str());
  text += format_text(
      "  %d iterations, %d residual / %d Jacobian evaluations, cost %.6e -> %.6e, "
      "solve %.3f ms\n",
      s.iterations, s.residual_evaluations, s.jacobian_evaluations, s.initial_cost, s.final_cost,
      1e3 * run.solve_seconds);
  text += format_text("validation over %d poses:\n", o.num_validation);
  print_errors(text, "before", run.before);
  print_errors(text, "after", run.after);
  const FitCheck fit = simulated_fit_check(scenario, run);
  if (fit.too_large())  // only a flagged fit: the JSON holds the check either way
    text += format_text(
        "fit check: chi-square %.4g on %d degrees of freedom against the simulated "
        "noise, P(larger) %.3g: %s\n",
        fit.chi_square, fit.degrees_of_freedom, fit.p_larger, kFitTooLarge);
  text += format_text("parameter RMS error after calibration:");
  bool first = true;
  for (const std::string& unit : parameter_units) {
    text += format_text("%s %.6g %s", first ? "" : ",", run.parameter_rms_errors.get(unit, 0),
                        unit.c_str());
    first = false;
  }
  text += format_text(" (%zu free parameters)\n", scenario.free_indices.size());
}

}  // namespace

nlohmann::json to_json(const PoseErrorStats& stats) {
  // JSON has no infinity: a model that cannot reach a pose reports null and the count.
  auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  return {{"position_mean_mm", number(stats.position_mean_mm)},
          {"position_max_mm", number(stats.position_max_mm)},
          {"orientation_mean_rad", number(stats.orientation_mean_rad)},
          {"orientation_max_rad", number(stats.orientation_max_rad)},
          {"fk_failures", stats.fk_failures}};
}

namespace {

// The range shared by every actuator in `unit`, or null when they differ or there is none.
nlohmann::json common_range(const Scenario& scenario, const std::string& unit) {
  nlohmann::json value;
  const auto& actuators = scenario.model->mechanism().actuators();
  for (std::size_t i = 0; i < actuators.size(); ++i) {
    if (actuators[i].unit != unit) continue;
    const double r = scenario.actuator_ranges[static_cast<int>(i)];
    if (!value.is_null() && value.get<double>() != r) return nlohmann::json();
    value = r;
  }
  return value;
}

}  // namespace

nlohmann::json to_json(const Scenario& scenario, const CalibrationRun& run, int case_id,
                       const std::string& model_name) {
  const Summary& summary = run.summary;
  nlohmann::json out;
  out["solver"] = summary.solver;
  out["formulation"] = to_string(run.formulation);
  out["formulation_note"] = run.formulation_note;
  out["termination"] = to_string(summary.termination);
  out["message"] = summary.message;
  out["backend_code"] = summary.backend_code;
  out["iterations"] = summary.iterations;
  out["solve_seconds"] = run.solve_seconds;
  out["initial_cost"] = summary.initial_cost;
  out["final_cost"] = summary.final_cost;
  out["residual_evaluations"] = summary.residual_evaluations;
  out["jacobian_evaluations"] = summary.jacobian_evaluations;
  const ScenarioOptions& o = scenario.options;
  const Mechanism& mechanism = scenario.model->mechanism();
  nlohmann::json ranges = nlohmann::json::object();
  for (int i = 0; i < mechanism.num_actuators(); ++i)
    ranges[mechanism.actuators()[i].name] = scenario.actuator_ranges[i];
  out["scenario"] = {
      {"case", case_id == 0 ? nlohmann::json() : nlohmann::json(case_id)},
      {"model", model_name},
      {"poses", o.num_configurations},
      {"noise_half_width_mm", o.noise_for(kMillimetre)},
      {"noise_half_width_rad", o.noise_for(kRadian)},
      {"param_error_half_width_mm", o.param_error_for(kMillimetre)},
      {"param_error_half_width_rad", o.param_error_for(kRadian)},
      {"config_range_mm", common_range(scenario, kMillimetre)},
      {"config_range_rad", common_range(scenario, kRadian)},
      {"actuator_ranges", ranges},
      {"validation_poses", o.num_validation},
      {"seed", o.seed},
      {"prior_std_mm", o.prior_std_for(kMillimetre) > 0
                           ? nlohmann::json(o.prior_std_for(kMillimetre))
                           : nlohmann::json()},
      {"prior_std_rad",
       o.prior_std_for(kRadian) > 0 ? nlohmann::json(o.prior_std_for(kRadian)) : nlohmann::json()}};
  // Units beyond mm and rad (px, a plug-in's), per unit: the keys above are for mm and rad.
  for (const UnitValues* values : {&o.noise_half_width, &o.param_error_half_width, &o.prior_std})
    for (const auto& [unit, value] : values->values())
      if (unit != kMillimetre && unit != kRadian) {
        const char* key = values == &o.noise_half_width         ? "noise_half_width"
                          : values == &o.param_error_half_width ? "param_error_half_width"
                                                                : "prior_std";
        out["scenario"][std::string(key) + "_" + unit] = value;
      }
  out["parameter_rms_error_mm"] = run.parameter_rms_error;
  out["parameter_rms_error_rad"] = run.parameter_rms_error_rad;
  nlohmann::json params = nlohmann::json::array();
  for (int i : scenario.free_indices) {
    const Parameter& p = scenario.model->parameters()[i];
    const bool angle = p.unit == kRadian;
    params.push_back({{"name", p.name},
                      {"unit", p.unit},
                      {"nominal", scenario.nominal[i]},
                      {"true", scenario.truth[i]},
                      // An angle on the branch nearest its nominal, as calibrate reports it.
                      {"estimate", angle ? scenario.nominal[i] +
                                               wrap_angle(run.estimate[i] - scenario.nominal[i])
                                         : run.estimate[i]}});
  }
  out["parameters"] = params;
  out["validation"] = {{"before", to_json(run.before)}, {"after", to_json(run.after)}};
  nlohmann::json trace = nlohmann::json::array();
  for (std::size_t i = 0; i < summary.trace.size(); ++i) {
    const IterationRecord& r = summary.trace[i];
    nlohmann::json row = {
        {"iteration", r.iteration}, {"cost", r.cost},       {"gradient_norm", r.gradient_norm},
        {"step_norm", r.step_norm}, {"damping", r.damping}, {"seconds", r.seconds}};
    if (i < run.trace_errors.size()) {
      const nlohmann::json e = to_json(run.trace_errors[i]);
      row["position_mean_mm"] = e["position_mean_mm"];
      row["orientation_mean_rad"] = e["orientation_mean_rad"];
    }
    trace.push_back(row);
  }
  out["trace"] = trace;
  return out;
}

std::string simulation_trace_csv(const CalibrationRun& run) {
  std::ostringstream out;
  out.precision(10);
  out << "iteration,cost,gradient_norm,step_norm,seconds,position_mean_mm,position_max_mm,"
         "orientation_mean_rad,orientation_max_rad\n";
  for (std::size_t i = 0; i < run.summary.trace.size(); ++i) {
    const IterationRecord& r = run.summary.trace[i];
    out << r.iteration << ',' << r.cost << ',' << r.gradient_norm << ',' << r.step_norm << ','
        << r.seconds;
    if (i < run.trace_errors.size()) {
      const PoseErrorStats& e = run.trace_errors[i];
      out << ',' << e.position_mean_mm << ',' << e.position_max_mm << ',' << e.orientation_mean_rad
          << ',' << e.orientation_max_rad;
    } else {
      out << ",,,,";
    }
    out << '\n';
  }
  return out.str();
}

std::string simulation_text(const SimulateResult& result) {
  std::string text;
  if (!result.design_text.empty()) text += result.design_text + "\n";
  print_report(text, result.scenario, result.run, result.case_id, result.model_name);
  return text + starts_text(result.starts);
}

nlohmann::json simulation_json(const SimulateResult& result) {
  const Scenario& scenario = result.scenario;
  const CalibrationRun& run = result.run;
  auto json = to_json(scenario, run, result.case_id, result.model_name);
  json["format"] = "kincal-simulate";  // keys are sorted in this document
  json["version"] = 1;
  json["design"] =
      result.design_text.empty() ? nlohmann::json() : nlohmann::json(result.design_text);
  json["fixed_by_identifiability"] = result.fixed_by_identifiability;
  const FitCheck fit = simulated_fit_check(scenario, run);
  json["fit_check"] = {
      {"verdict", !fit.tested       ? "not_tested"
                  : fit.too_large() ? "too_large"
                                    : "consistent"},
      {"chi_square", fit.tested ? nlohmann::json(fit.chi_square) : nlohmann::json()},
      {"degrees_of_freedom",
       fit.tested ? nlohmann::json(fit.degrees_of_freedom) : nlohmann::json()},
      {"p_larger", fit.tested ? nlohmann::json(fit.p_larger) : nlohmann::json()},
      {"note", fit.tested ? (fit.too_large() ? kFitTooLarge : kFitConsistent) : fit.not_tested}};
  json["starts"] = starts_json(result.starts);
  // Where the configurations and the truth came from (null: drawn from the seed).
  json["configs"] =
      result.configs_file.empty() ? nlohmann::json() : nlohmann::json(result.configs_file);
  json["truth_model"] =
      result.truth_file.empty() ? nlohmann::json() : nlohmann::json(result.truth_file);
  return json;
}

std::string simulated_data_csv(const SimulateResult& result, const std::string& truth_path,
                               const std::string& truth_text) {
  const ScenarioOptions& o = result.scenario.options;
  const MeasurementModel& model = *result.scenario.model;
  char noise[96];
  std::snprintf(noise, sizeof noise, "%g mm, %g rad", o.noise_for(kMillimetre),
                o.noise_for(kRadian));
  std::string other_noise;  // units beyond mm and rad
  for (const auto& [unit, value] : o.noise_half_width.values())
    if (unit != kMillimetre && unit != kRadian)
      other_noise += format_text(", %g %s", value, unit.c_str());
  const std::string comment =
      "kincal simulate: " + printable(result.model_name) + ", " +
      std::to_string(o.num_configurations) + " configurations" +
      (!result.configs_file.empty() ? " of " + printable(result.configs_file) : std::string()) +
      ", reading noise U[-a, a] with a = " + noise + other_noise + ", seed " +
      std::to_string(o.seed) +
      (!result.truth_file.empty() ? ", true model given by --truth " + printable(result.truth_file)
                                  : std::string()) +
      "\ntrue model: " + printable(truth_path) + " (sha256 " + sha256_hex(truth_text) + ")";
  return measurements_to_csv(result.scenario.calibration, model.mechanism().actuator_names(),
                             model.reading_names(), comment);
}

}  // namespace kincal
