#include "kincal/cli/simulation_report.hpp"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "kincal/cli/shared_options.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal::cli {

void add_scenario_options(po::options_description& options, bool with_case_and_poses) {
  if (with_case_and_poses) {
    options.add_options()("case", po::value<int>(),
                          "paper's Table 2 case 1..5 (sets --noise-half-width and --poses)")(
        "poses", po::value<int>(), "number of measured configurations (default 30)")(
        "noise-half-width", po::value<std::string>(),
        "reading noise as the paper states it, a half-width a per unit, e.g. 0.00125mm or "
        "0.05mm,1e-4rad: each reading gets U[-a, a] (default 0; a bare number is mm; "
        "--noise-std states the same noise as its std, a / sqrt(3))");
    add_deprecated_alias(options, "noise", "noise-half-width", po::value<std::string>());
  }
  options.add_options()("param-error", po::value<std::string>()->default_value("5mm,0.01rad"),
                        "true parameters = nominal + U[-e, e] on each free parameter, e per "
                        "unit (a parameter's own param_error in the model file wins); 0 is "
                        "zero in every unit: the model is the truth")(
      "seed", po::value<Seed>()->default_value(Seed{1}, "1"), "random seed")(
      "validation", po::value<int>()->default_value(200),
      "validation configurations for the pose errors");
  add_config_range_option(options);
}

UnitValues unit_values_option(const po::variables_map& vm, const std::string& option) {
  const std::string text = vm[option].as<std::string>();
  UnitValues values;
  try {
    values = UnitValues::parse(text);
  } catch (const std::invalid_argument& e) {
    throw CliError(option_flag(option) + " '" + text + "': " + e.what());
  }
  for (const auto& [unit, value] : values.values())
    if (!(value >= 0))
      throw CliError(option_flag(option) + " '" + text + "': expected values >= 0");
  return values;
}

ScenarioOptions scenario_options_from(const po::variables_map& vm, int* case_id) {
  ScenarioOptions s;
  *case_id = 0;
  if (vm.count("case")) {
    if (vm.count("poses") || vm.count("noise-half-width"))
      throw CliError("--case sets --poses and --noise-half-width; give either --case or those two");
    *case_id = vm["case"].as<int>();
    try {
      const PaperCase& c = paper_case(*case_id);
      s.num_configurations = c.num_configurations;
      s.noise_half_width = c.noise_half_width;
    } catch (const std::invalid_argument& e) {
      throw CliError(std::string("--case: ") + e.what());
    }
  }
  if (vm.count("poses")) s.num_configurations = vm["poses"].as<int>();
  if (vm.count("noise-half-width")) {
    const UnitValues noise = unit_values_option(vm, "noise-half-width");
    s.noise_half_width = noise.get(kMillimetre, 0);
    s.noise_half_width_rad = noise.get(kRadian, 0);
  }
  const UnitValues error = unit_values_option(vm, "param-error");
  // "--param-error 0" is the truth itself: zero in every unit, not only in the bare number's
  // (mm), which left the angles drawn at ±0.01 rad.
  const std::string error_text = vm["param-error"].as<std::string>();
  char* end = nullptr;
  const bool bare_zero =
      std::strtod(error_text.c_str(), &end) == 0 && end != error_text.c_str() && *end == '\0';
  s.param_error_half_width = bare_zero ? 0 : error.get(kMillimetre, s.param_error_half_width);
  s.param_error_half_width_rad = bare_zero ? 0 : error.get(kRadian, s.param_error_half_width_rad);
  if (vm.count("config-range")) {
    const UnitValues range = unit_values_option(vm, "config-range");
    s.config_range = range.get(kMillimetre, s.config_range);
    s.config_range_rad = range.get(kRadian, s.config_range_rad);
  }
  s.seed = vm["seed"].as<Seed>().value;
  s.num_validation = vm["validation"].as<int>();
  if (s.num_configurations < 1) throw CliError("--poses must be at least 1");
  if (s.num_validation < 1) throw CliError("--validation must be at least 1");
  return s;
}

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
      {"noise_half_width_mm", o.noise_half_width},
      {"noise_half_width_rad", o.noise_half_width_rad},
      {"param_error_half_width_mm", o.param_error_half_width},
      {"param_error_half_width_rad", o.param_error_half_width_rad},
      {"config_range_mm", common_range(scenario, kMillimetre)},
      {"config_range_rad", common_range(scenario, kRadian)},
      {"actuator_ranges", ranges},
      {"validation_poses", o.num_validation},
      {"seed", o.seed},
      {"prior_std_mm", o.prior_std > 0 ? nlohmann::json(o.prior_std) : nlohmann::json()},
      {"prior_std_rad", o.prior_std_rad > 0 ? nlohmann::json(o.prior_std_rad) : nlohmann::json()}};
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

std::string trace_csv(const CalibrationRun& run) {
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

}  // namespace kincal::cli
