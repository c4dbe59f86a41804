#include "kincal/cli/simulation_report.hpp"

#include <cmath>
#include <sstream>

namespace kincal::cli {

void add_scenario_options(po::options_description& options, bool with_case_and_poses) {
  if (with_case_and_poses)
    options.add_options()("case", po::value<int>(),
                          "paper's Table 2 case 1..5 (sets --noise and --poses)")(
        "poses", po::value<int>(), "number of measured configurations (default 30)")(
        "noise", po::value<double>(), "gauge noise half-width a in mm: U[-a, a] (default 0)");
  options.add_options()("param-error", po::value<double>()->default_value(5.0),
                        "true parameters = nominal + U[-e, e] mm on each free parameter")(
      "config-range", po::value<double>()->default_value(20.0),
      "configurations = home leg lengths + U[-r, r] mm per leg")(
      "seed", po::value<Seed>()->default_value(Seed{1}, "1"), "random seed")(
      "validation", po::value<int>()->default_value(200),
      "validation configurations for the pose errors");
}

ScenarioOptions scenario_options_from(const po::variables_map& vm, int* case_id) {
  ScenarioOptions s;
  *case_id = 0;
  if (vm.count("case")) {
    if (vm.count("poses") || vm.count("noise"))
      throw CliError("--case sets --poses and --noise; give either --case or those two");
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
  if (vm.count("noise")) s.noise_half_width = vm["noise"].as<double>();
  s.param_error_half_width = vm["param-error"].as<double>();
  s.config_range = vm["config-range"].as<double>();
  s.seed = vm["seed"].as<Seed>().value;
  s.num_validation = vm["validation"].as<int>();
  if (s.num_configurations < 1) throw CliError("--poses must be at least 1");
  if (!(s.noise_half_width >= 0) || !std::isfinite(s.noise_half_width))
    throw CliError("--noise must be a finite number >= 0");
  if (!(s.param_error_half_width >= 0) || !std::isfinite(s.param_error_half_width))
    throw CliError("--param-error must be a finite number >= 0");
  if (!(s.config_range >= 0) || !std::isfinite(s.config_range))
    throw CliError("--config-range must be a finite number >= 0");
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

nlohmann::json to_json(const Scenario& scenario, const CalibrationRun& run, int case_id) {
  const Summary& summary = run.summary;
  nlohmann::json out;
  out["solver"] = summary.solver;
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
  out["scenario"] = {{"case", case_id == 0 ? nlohmann::json() : nlohmann::json(case_id)},
                     {"poses", o.num_configurations},
                     {"noise_half_width_mm", o.noise_half_width},
                     {"param_error_half_width_mm", o.param_error_half_width},
                     {"config_range_mm", o.config_range},
                     {"validation_poses", o.num_validation},
                     {"seed", o.seed}};
  out["parameter_rms_error_mm"] = run.parameter_rms_error;
  nlohmann::json params = nlohmann::json::array();
  for (int i : scenario.free_indices)
    params.push_back({{"name", scenario.model->parameters()[i].name},
                      {"nominal", scenario.nominal[i]},
                      {"true", scenario.truth[i]},
                      {"estimate", run.estimate[i]}});
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
