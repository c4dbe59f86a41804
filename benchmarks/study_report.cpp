#include "benchmarks/study_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "kincal/framework/base/statistics.hpp"

namespace kincal::bench {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

template <class F>
std::vector<double> collect(const std::vector<TrialRecord>& trials, F field) {
  std::vector<double> v;
  for (const auto& t : trials)
    if (t.ran) v.push_back(field(t));
  return v;
}

// Root of the mean of squares over the finite values.
double rms(const std::vector<double>& values) {
  double sum = 0;
  int n = 0;
  for (double v : values)
    if (std::isfinite(v)) sum += v * v, ++n;
  return n ? std::sqrt(sum / n) : kNaN;
}

std::ofstream open(const std::string& directory, const std::string& name) {
  std::ofstream out(std::filesystem::path(directory) / name);
  if (!out) throw std::runtime_error("cannot write " + directory + "/" + name);
  out.precision(10);
  return out;
}

std::string format(const char* fmt, double value) {
  if (!std::isfinite(value)) return std::isnan(value) ? "–" : "inf";
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, value);
  return buf;
}

}  // namespace

CaseBound summarize_bound(const StudyResults& results, int case_index) {
  CaseBound b;
  b.case_id = results.cases[case_index].id;
  std::vector<double> cond;
  double p = 0, t = 0, o = 0;
  int n = 0;
  for (const CramerRaoPrediction& c : results.cramer_rao[case_index]) {
    if (!c.ok) continue;
    cond.push_back(c.condition_number);
    p += c.parameter_mean_square, t += c.position_mean_square, o += c.orientation_mean_square;
    ++n;
  }
  b.condition_number_median = median(cond);
  b.parameter_rms = n ? std::sqrt(p / n) : kNaN;
  b.position_rms = n ? std::sqrt(t / n) : kNaN;
  b.orientation_rms = n ? std::sqrt(o / n) : kNaN;
  return b;
}

CellSummary summarize_cell(const StudyResults& results, int case_index, int solver_index) {
  const auto& trials = results.trials[case_index][solver_index];
  CellSummary s;
  s.case_id = results.cases[case_index].id;
  s.solver = results.solvers[solver_index];
  for (const auto& t : trials) {
    if (!t.ran) continue;
    ++s.trials;
    switch (t.termination) {
      case TerminationType::kConverged:
        ++s.converged;
        break;
      case TerminationType::kMaxIterations:
        ++s.max_iterations;
        break;
      case TerminationType::kDiverged:
        ++s.diverged;
        break;
      case TerminationType::kFailed:
        ++s.failed;
        break;
      case TerminationType::kUserStopped:
        ++s.user_stopped;
        break;
    }
  }
  if (s.trials == 0) return s;
  const auto param = collect(trials, [](const TrialRecord& t) { return t.parameter_rms; });
  const auto pos = collect(trials, [](const TrialRecord& t) { return t.position_mean; });
  const auto ori = collect(trials, [](const TrialRecord& t) { return t.orientation_mean; });
  const auto secs = collect(trials, [](const TrialRecord& t) { return t.solve_seconds; });
  s.parameter_rms_median = median(param), s.parameter_rms_p90 = quantile(param, 0.9);
  s.position_mean_median = median(pos), s.position_mean_p90 = quantile(pos, 0.9);
  s.orientation_mean_median = median(ori), s.orientation_mean_p90 = quantile(ori, 0.9);
  s.seconds_median = median(secs), s.seconds_p90 = quantile(secs, 0.9);
  s.iterations_median =
      median(collect(trials, [](const TrialRecord& t) { return double(t.iterations); }));
  s.residual_evaluations_median =
      median(collect(trials, [](const TrialRecord& t) { return double(t.residual_evaluations); }));
  s.jacobian_evaluations_median =
      median(collect(trials, [](const TrialRecord& t) { return double(t.jacobian_evaluations); }));
  s.mc_parameter_rms = rms(param);
  s.mc_position_rms = rms(collect(trials, [](const TrialRecord& t) { return t.position_rms; }));
  s.mc_orientation_rms =
      rms(collect(trials, [](const TrialRecord& t) { return t.orientation_rms; }));
  // The bound over the same trials (cells with fewer trials compare like with like).
  double p = 0, t = 0, o = 0;
  int n = 0;
  for (std::size_t i = 0; i < trials.size(); ++i) {
    const CramerRaoPrediction& c = results.cramer_rao[case_index][i];
    if (!trials[i].ran || !c.ok) continue;
    p += c.parameter_mean_square, t += c.position_mean_square, o += c.orientation_mean_square;
    ++n;
  }
  const bool noisy = results.cases[case_index].scenario.noise_for(kincal::kMillimetre) > 0 && n > 0;
  s.efficiency_parameters = noisy ? s.mc_parameter_rms / std::sqrt(p / n) : kNaN;
  s.efficiency_position = noisy ? s.mc_position_rms / std::sqrt(t / n) : kNaN;
  s.efficiency_orientation = noisy ? s.mc_orientation_rms / std::sqrt(o / n) : kNaN;
  return s;
}

namespace {

nlohmann::json to_json(const CellSummary& s) {
  return {{"case", s.case_id},
          {"solver", s.solver},
          {"trials", s.trials},
          {"parameter_rms_mm", {{"median", s.parameter_rms_median}, {"p90", s.parameter_rms_p90}}},
          {"position_mean_mm", {{"median", s.position_mean_median}, {"p90", s.position_mean_p90}}},
          {"orientation_mean_rad",
           {{"median", s.orientation_mean_median}, {"p90", s.orientation_mean_p90}}},
          {"iterations_median", s.iterations_median},
          {"residual_evaluations_median", s.residual_evaluations_median},
          {"jacobian_evaluations_median", s.jacobian_evaluations_median},
          {"solve_seconds", {{"median", s.seconds_median}, {"p90", s.seconds_p90}}},
          {"termination",
           {{"converged", s.converged},
            {"max_iterations", s.max_iterations},
            {"diverged", s.diverged},
            {"failed", s.failed},
            {"user_stopped", s.user_stopped}}},
          {"monte_carlo_rms",
           {{"parameters_mm", s.mc_parameter_rms},
            {"position_mm", s.mc_position_rms},
            {"orientation_rad", s.mc_orientation_rms}}},
          {"efficiency",
           {{"parameters", s.efficiency_parameters},
            {"position", s.efficiency_position},
            {"orientation", s.efficiency_orientation}}}};
}

void write_summary_csv(const StudyResults& results, const std::string& directory) {
  auto out = open(directory, "summary.csv");
  out << "case,solver,trials,parameter_rms_median_mm,parameter_rms_p90_mm,"
         "position_mean_median_mm,position_mean_p90_mm,orientation_mean_median_rad,"
         "orientation_mean_p90_rad,iterations_median,residual_evaluations_median,"
         "jacobian_evaluations_median,solve_seconds_median,solve_seconds_p90,converged,"
         "max_iterations,diverged,failed,user_stopped,mc_parameter_rms_mm,mc_position_rms_mm,"
         "mc_orientation_rms_rad,efficiency_parameters,efficiency_position,"
         "efficiency_orientation\n";
  for (std::size_t c = 0; c < results.cases.size(); ++c) {
    for (std::size_t k = 0; k < results.solvers.size(); ++k) {
      const CellSummary s = summarize_cell(results, c, k);
      if (s.trials == 0) continue;
      out << s.case_id << ',' << s.solver << ',' << s.trials << ',' << s.parameter_rms_median << ','
          << s.parameter_rms_p90 << ',' << s.position_mean_median << ',' << s.position_mean_p90
          << ',' << s.orientation_mean_median << ',' << s.orientation_mean_p90 << ','
          << s.iterations_median << ',' << s.residual_evaluations_median << ','
          << s.jacobian_evaluations_median << ',' << s.seconds_median << ',' << s.seconds_p90 << ','
          << s.converged << ',' << s.max_iterations << ',' << s.diverged << ',' << s.failed << ','
          << s.user_stopped << ',' << s.mc_parameter_rms << ',' << s.mc_position_rms << ','
          << s.mc_orientation_rms << ',' << s.efficiency_parameters << ',' << s.efficiency_position
          << ',' << s.efficiency_orientation << '\n';
    }
  }
}

void write_bounds_csv(const StudyResults& results, const std::string& directory) {
  auto out = open(directory, "bounds.csv");
  out << "case,description,noise_half_width_mm,configurations,param_error_half_width_mm,"
         "condition_number_median,crb_parameter_rms_mm,crb_position_rms_mm,"
         "crb_orientation_rms_rad\n";
  for (std::size_t c = 0; c < results.cases.size(); ++c) {
    const StudyCase& sc = results.cases[c];
    const CaseBound b = summarize_bound(results, c);
    out << sc.id << ",\"" << sc.description << "\"," << sc.scenario.noise_for(kincal::kMillimetre)
        << ',' << sc.scenario.num_configurations << ','
        << sc.scenario.param_error_for(kincal::kMillimetre) << ',' << b.condition_number_median
        << ',' << b.parameter_rms << ',' << b.position_rms << ',' << b.orientation_rms << '\n';
  }
}

void write_trials_csv(const StudyResults& results, const std::string& directory) {
  auto out = open(directory, "trials.csv");
  out << "case,solver,trial,termination,iterations,residual_evaluations,jacobian_evaluations,"
         "solve_seconds,parameter_rms_mm,position_mean_mm,orientation_mean_rad,"
         "position_rms_mm,orientation_rms_rad,crb_parameter_rms_mm\n";
  for (std::size_t c = 0; c < results.cases.size(); ++c)
    for (std::size_t k = 0; k < results.solvers.size(); ++k)
      for (std::size_t t = 0; t < results.trials[c][k].size(); ++t) {
        const TrialRecord& r = results.trials[c][k][t];
        if (!r.ran) continue;
        out << results.cases[c].id << ',' << results.solvers[k] << ',' << t << ','
            << to_string(r.termination) << ',' << r.iterations << ',' << r.residual_evaluations
            << ',' << r.jacobian_evaluations << ',' << r.solve_seconds << ',' << r.parameter_rms
            << ',' << r.position_mean << ',' << r.orientation_mean << ',' << r.position_rms << ','
            << r.orientation_rms << ',' << std::sqrt(results.cramer_rao[c][t].parameter_mean_square)
            << '\n';
      }
}

// Quantiles over trials of the validation errors at each iteration; a trial that stopped
// earlier contributes its final value (its model no longer changes).
void write_traces_csv(const StudyResults& results, const std::string& directory) {
  auto out = open(directory, "traces.csv");
  out << "case,solver,iteration,trials,running,position_p10_mm,position_p25_mm,position_median_mm,"
         "position_p75_mm,position_p90_mm,orientation_p10_rad,orientation_p25_rad,"
         "orientation_median_rad,orientation_p75_rad,orientation_p90_rad\n";
  const double qs[5] = {0.1, 0.25, 0.5, 0.75, 0.9};
  for (std::size_t c = 0; c < results.cases.size(); ++c)
    for (std::size_t k = 0; k < results.solvers.size(); ++k) {
      const auto& trials = results.trials[c][k];
      std::size_t length = 0;
      for (const auto& t : trials) length = std::max(length, t.trace.size());
      for (std::size_t i = 0; i < length; ++i) {
        std::vector<double> pos, ori;
        int running = 0;  // trials still iterating at this iteration
        for (const auto& t : trials) {
          if (t.trace.empty()) continue;
          running += i < t.trace.size();
          const PoseErrorStats& e = t.trace[std::min(i, t.trace.size() - 1)];
          pos.push_back(e.position_mean_mm);
          ori.push_back(e.orientation_mean_rad);
        }
        out << results.cases[c].id << ',' << results.solvers[k] << ',' << i << ',' << pos.size()
            << ',' << running;
        for (double q : qs) out << ',' << quantile(pos, q);
        for (double q : qs) out << ',' << quantile(ori, q);
        out << '\n';
      }
    }
}

void write_json(const StudyResults& results, const std::string& directory) {
  nlohmann::json j;
  const StudyOptions& o = results.options;
  j["options"] = {{"trials", o.trials},
                  {"seed", o.seed},
                  {"validation_poses", o.validation},
                  {"max_iterations", o.max_iterations},
                  {"nlopt_gradient_evaluations", o.nlopt_gradient_evaluations},
                  {"nlopt_derivative_free_evaluations", o.nlopt_derivative_free_evaluations},
                  {"derivative_free_cases", o.derivative_free_cases},
                  {"nlopt_limited_cases", o.nlopt_limited_cases},
                  {"limited_trials", o.limited_trials},
                  {"excluded_solvers", o.excluded_solvers},
                  {"tracked_solvers", o.tracked_solvers}};
  j["wall_seconds"] = results.wall_seconds;
  j["solvers"] = results.solvers;
  for (std::size_t c = 0; c < results.cases.size(); ++c) {
    const StudyCase& sc = results.cases[c];
    const CaseBound b = summarize_bound(results, c);
    nlohmann::json jc = {
        {"id", sc.id},
        {"description", sc.description},
        {"noise_half_width_mm", sc.scenario.noise_for(kincal::kMillimetre)},
        {"configurations", sc.scenario.num_configurations},
        {"param_error_half_width_mm", sc.scenario.param_error_for(kincal::kMillimetre)},
        {"cramer_rao",
         {{"condition_number_median", b.condition_number_median},
          {"parameter_rms_mm", b.parameter_rms},
          {"position_rms_mm", b.position_rms},
          {"orientation_rms_rad", b.orientation_rms}}}};
    for (std::size_t k = 0; k < results.solvers.size(); ++k) {
      const CellSummary s = summarize_cell(results, c, k);
      if (s.trials > 0) jc["cells"].push_back(to_json(s));
    }
    j["cases"].push_back(jc);
  }
  auto out = open(directory, "summary.json");
  out << j.dump(2) << '\n';
}

void write_markdown(const StudyResults& results, const std::string& directory) {
  auto out = open(directory, "accuracy.md");
  const StudyOptions& o = results.options;
  out << "Monte Carlo over " << o.trials << " seeds per case (seed " << o.seed << "), "
      << o.validation << " validation poses per trial; study wall time "
      << format("%.0f", results.wall_seconds) << " s.\n\n";
  out << "**Cramér-Rao prediction** (σ = a/√3, covariance σ²(JᵀJ)⁻¹ at the true parameters, "
         "RMS over trials; validation errors propagated through J_pose_params):\n\n";
  out << "| case | what | a (mm) | m | param. error | cond(J) median | param. RMS (mm) | "
         "position RMS (mm) | orientation RMS (mrad) |\n";
  out << "|---|---|---|---|---|---|---|---|---|\n";
  for (std::size_t c = 0; c < results.cases.size(); ++c) {
    const StudyCase& sc = results.cases[c];
    const CaseBound b = summarize_bound(results, c);
    out << "| " << sc.id << " | " << sc.description << " | "
        << sc.scenario.noise_for(kincal::kMillimetre) << " | " << sc.scenario.num_configurations
        << " | ±" << sc.scenario.param_error_for(kincal::kMillimetre) << " mm | "
        << format("%.2g", b.condition_number_median) << " | " << format("%.3g", b.parameter_rms)
        << " | " << format("%.3g", b.position_rms) << " | "
        << format("%.3g", 1e3 * b.orientation_rms) << " |\n";
  }
  out << "\n**Per case and backend**: median (p90) over trials; position and orientation are "
         "means over the validation poses; eff. = Monte Carlo RMS / Cramér-Rao RMS (parameters, "
         "position); outcome = converged / max_iterations / diverged / failed.\n\n";
  out << "| case | backend | trials | param. RMS (mm) | position (mm) | orientation (mrad) | "
         "iter. | evals r/J | time (ms) | outcome | eff. param. | eff. position |\n";
  out << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (std::size_t c = 0; c < results.cases.size(); ++c)
    for (std::size_t k = 0; k < results.solvers.size(); ++k) {
      const CellSummary s = summarize_cell(results, c, k);
      if (s.trials == 0) continue;
      out << "| " << s.case_id << " | " << s.solver << " | " << s.trials << " | "
          << format("%.3g", s.parameter_rms_median) << " (" << format("%.3g", s.parameter_rms_p90)
          << ") | " << format("%.3g", s.position_mean_median) << " ("
          << format("%.3g", s.position_mean_p90) << ") | "
          << format("%.3g", 1e3 * s.orientation_mean_median) << " ("
          << format("%.3g", 1e3 * s.orientation_mean_p90) << ") | "
          << format("%.0f", s.iterations_median) << " | "
          << format("%.0f", s.residual_evaluations_median) << "/"
          << format("%.0f", s.jacobian_evaluations_median) << " | "
          << format("%.3g", 1e3 * s.seconds_median) << " | " << s.converged << "/"
          << s.max_iterations << "/" << s.diverged << "/" << s.failed
          << (s.user_stopped ? "/" + std::to_string(s.user_stopped) + " stopped" : "") << " | "
          << format("%.2f", s.efficiency_parameters) << " | "
          << format("%.2f", s.efficiency_position) << " |\n";
    }
}

}  // namespace

void write_study_files(const StudyResults& results, const std::string& directory) {
  std::filesystem::create_directories(directory);
  write_summary_csv(results, directory);
  write_bounds_csv(results, directory);
  write_trials_csv(results, directory);
  write_traces_csv(results, directory);
  write_json(results, directory);
  write_markdown(results, directory);
}

}  // namespace kincal::bench
