#include "kincal/framework/workflows/reproduce.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "kincal/framework/base/random.hpp"
#include "kincal/framework/base/statistics.hpp"

namespace kincal {

namespace {

template <class F>
std::vector<double> collect(const std::vector<ReproduceTrial>& trials, F field) {
  std::vector<double> v;
  v.reserve(trials.size());
  for (const auto& t : trials) v.push_back(field(t));
  return v;
}

// The trials that ran (all of them unless the run was interrupted).
std::vector<ReproduceTrial> finished(const std::vector<ReproduceTrial>& trials) {
  std::vector<ReproduceTrial> out;
  for (const auto& t : trials)
    if (t.done) out.push_back(t);
  return out;
}

// The median, or NaN (null in JSON, empty in CSV) over no trials.
double median_or_nan(const std::vector<double>& v) {
  return v.empty() ? std::numeric_limits<double>::quiet_NaN() : median(v);
}
double p90_or_nan(const std::vector<double>& v) {
  return v.empty() ? std::numeric_limits<double>::quiet_NaN() : quantile(v, 0.9);
}

nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

int count(const std::vector<ReproduceTrial>& trials, TerminationType type) {
  return static_cast<int>(std::count_if(trials.begin(), trials.end(), [&](const ReproduceTrial& t) {
    return t.termination == type;
  }));
}

// Mean over trials of the validation error at each iteration; a trial that stopped earlier
// contributes its final value (its model no longer changes).
std::vector<std::array<double, 2>> mean_trace(const std::vector<ReproduceTrial>& trials) {
  std::size_t length = 0;
  for (const auto& t : trials) length = std::max(length, t.trace.size());
  std::vector<std::array<double, 2>> mean(length, {0.0, 0.0});
  int used = 0;
  for (const auto& t : trials) {
    if (t.trace.empty()) continue;
    ++used;
    for (std::size_t i = 0; i < length; ++i) {
      const PoseErrorStats& e = t.trace[std::min(i, t.trace.size() - 1)];
      mean[i][0] += e.position_mean_mm;
      mean[i][1] += e.orientation_mean_rad;
    }
  }
  for (auto& m : mean) m[0] /= std::max(used, 1), m[1] /= std::max(used, 1);
  return mean;
}

}  // namespace

ReproduceTrial run_reproduce_trial(const std::shared_ptr<const MeasurementModel>& model,
                                   const ScenarioOptions& base, const PaperCase& paper, int trial,
                                   const Solver& solver, const SolverOptions& options) {
  ScenarioOptions o = base;
  o.num_configurations = paper.num_configurations;
  o.noise_half_width = UnitValues(paper.noise_half_width, 0);
  o.seed = derive_seed(base.seed, static_cast<std::uint64_t>(trial));
  const Scenario scenario = make_scenario(model, o);
  const CalibrationRun run = run_calibration(scenario, solver, options, true);
  ReproduceTrial r;
  r.termination = run.summary.termination;
  r.iterations = run.summary.iterations;
  r.parameter_rms = run.parameter_rms_error;
  r.seconds = run.solve_seconds;
  r.before = run.before;
  r.after = run.after;
  r.trace = run.trace_errors;
  r.done = true;
  return r;
}

ReproduceTables reproduce_tables(const std::vector<ReproduceCase>& cases, int num_trials,
                                 bool partial, const std::string& solver_name) {
  ReproduceTables tables;
  std::ostringstream summary_csv, trials_csv, trace_csv;
  summary_csv.precision(10);
  trials_csv.precision(10);
  trace_csv.precision(10);
  summary_csv << "case,noise_half_width_mm,poses,trials,solver,position_before_median_mm,"
                 "position_before_p90_mm,position_after_median_mm,position_after_p90_mm,"
                 "orientation_before_median_rad,orientation_before_p90_rad,"
                 "orientation_after_median_rad,orientation_after_p90_rad,"
                 "parameter_rms_median_mm,iterations_median,converged,max_iterations,diverged,"
                 "failed,user_stopped,trials_with_unreachable_validation_poses,partial\n";
  trials_csv << "case,trial,termination,iterations,solve_seconds,parameter_rms_mm,"
                "position_before_mm,orientation_before_rad,position_after_mm,"
                "orientation_after_rad,unreachable_validation_poses\n";
  trace_csv << "case,iteration,position_mean_mm,orientation_mean_rad\n";
  nlohmann::ordered_json& json_cases = tables.json_cases;
  json_cases = nlohmann::ordered_json::array();
  for (const ReproduceCase& c : cases) {
    const std::vector<ReproduceTrial> t = finished(c.trials);
    const auto pos_before =
        collect(t, [](const ReproduceTrial& r) { return r.before.position_mean_mm; });
    const auto pos_after =
        collect(t, [](const ReproduceTrial& r) { return r.after.position_mean_mm; });
    const auto ori_before =
        collect(t, [](const ReproduceTrial& r) { return r.before.orientation_mean_rad; });
    const auto ori_after =
        collect(t, [](const ReproduceTrial& r) { return r.after.orientation_mean_rad; });
    const auto iterations =
        collect(t, [](const ReproduceTrial& r) { return static_cast<double>(r.iterations); });
    const auto param_rms = collect(t, [](const ReproduceTrial& r) { return r.parameter_rms; });
    const int conv = count(t, TerminationType::kConverged);
    const int maxit = count(t, TerminationType::kMaxIterations);
    const int div = count(t, TerminationType::kDiverged);
    const int fail = count(t, TerminationType::kFailed);
    const int stopped = count(t, TerminationType::kUserStopped);
    // Validation means are over the poses the calibrated model reaches: say how many trials
    // had poses it could not reach, so that such a model does not look better than it is.
    const int unreachable = static_cast<int>(std::count_if(
        t.begin(), t.end(), [](const ReproduceTrial& r) { return r.after.fk_failures > 0; }));
    char outcome[64];
    std::snprintf(outcome, sizeof outcome, "%d/%d/%d/%d", conv, maxit, div, fail);
    const int n = static_cast<int>(t.size());
    // Over the trials that ran: all of them, or those finished before Ctrl-C (then the
    // trials column says how many, and the partial column says so).
    const double stats[] = {median_or_nan(pos_before), p90_or_nan(pos_before),
                            median_or_nan(pos_after),  p90_or_nan(pos_after),
                            median_or_nan(ori_before), p90_or_nan(ori_before),
                            median_or_nan(ori_after),  p90_or_nan(ori_after),
                            median_or_nan(param_rms),  median_or_nan(iterations)};
    char row[256];
    std::snprintf(
        row, sizeof row,
        "%-4d %-9g %5d | %10.4g %10.4g %10.4g | %10.4g %10.4g %10.4g | %5.0f | %-17s | %d\n",
        c.paper.id, c.paper.noise_half_width, c.paper.num_configurations, stats[0], stats[2],
        stats[3], stats[4], stats[6], stats[7], stats[9], outcome, unreachable);
    tables.text_rows += row;
    summary_csv << c.paper.id << ',' << c.paper.noise_half_width << ','
                << c.paper.num_configurations << ',' << n << ',' << solver_name;
    for (double v : stats) {
      summary_csv << ',';
      if (std::isfinite(v)) summary_csv << v;
    }
    summary_csv << ',' << conv << ',' << maxit << ',' << div << ',' << fail << ',' << stopped << ','
                << unreachable << ',' << (partial ? "true" : "false") << '\n';
    json_cases.push_back({{"case", c.paper.id},
                          {"noise_half_width_mm", c.paper.noise_half_width},
                          {"poses", c.paper.num_configurations},
                          {"trials", n},
                          {"position_before_median_mm", number(stats[0])},
                          {"position_before_p90_mm", number(stats[1])},
                          {"position_after_median_mm", number(stats[2])},
                          {"position_after_p90_mm", number(stats[3])},
                          {"orientation_before_median_rad", number(stats[4])},
                          {"orientation_before_p90_rad", number(stats[5])},
                          {"orientation_after_median_rad", number(stats[6])},
                          {"orientation_after_p90_rad", number(stats[7])},
                          {"parameter_rms_median_mm", number(stats[8])},
                          {"iterations_median", number(stats[9])},
                          {"converged", conv},
                          {"max_iterations", maxit},
                          {"diverged", div},
                          {"failed", fail},
                          {"user_stopped", stopped},
                          {"trials_with_unreachable_validation_poses", unreachable}});
    for (int i = 0; i < num_trials; ++i) {
      const ReproduceTrial& r = c.trials[i];
      if (!r.done) continue;
      trials_csv << c.paper.id << ',' << i << ',' << to_string(r.termination) << ',' << r.iterations
                 << ',' << r.seconds << ',' << r.parameter_rms << ',' << r.before.position_mean_mm
                 << ',' << r.before.orientation_mean_rad << ',' << r.after.position_mean_mm << ','
                 << r.after.orientation_mean_rad << ',' << r.after.fk_failures << '\n';
    }
    const auto trace = mean_trace(t);
    for (std::size_t i = 0; i < trace.size(); ++i)
      trace_csv << c.paper.id << ',' << i << ',' << trace[i][0] << ',' << trace[i][1] << '\n';
  }
  tables.summary_csv = summary_csv.str();
  tables.trials_csv = trials_csv.str();
  tables.trace_csv = trace_csv.str();
  return tables;
}

nlohmann::ordered_json reproduce_json(const std::string& solver_name, int num_trials, bool partial,
                                      const ScenarioOptions& base, const std::string& out_dir,
                                      const nlohmann::ordered_json& json_cases) {
  return {{"format", "kincal-reproduce"},
          {"version", 1},
          {"solver", solver_name},
          {"trials_per_case", num_trials},
          {"partial", partial},
          {"param_error_half_width_mm", base.param_error_for(kMillimetre)},
          {"validation_poses", base.num_validation},
          {"seed", base.seed},
          {"out", out_dir},
          {"cases", json_cases}};
}

}  // namespace kincal
