// kincal reproduce: the paper's five Table 2 cases as a Monte Carlo over seeds.
//
// Trial t of every case uses the seed derive_seed(--seed, t): the same true geometry in all
// five cases, and the same first configurations, so cases differ only in what Table 2
// changes (noise, number of configurations).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "kincal/cli/common_options.hpp"
#include "kincal/cli/interrupt.hpp"
#include "kincal/cli/memory_check.hpp"
#include "kincal/cli/progress.hpp"
#include "kincal/cli/simulation_report.hpp"
#include "kincal/framework/parallel.hpp"
#include "kincal/framework/random.hpp"
#include "kincal/framework/statistics.hpp"
#include "kincal/models/presets.hpp"

namespace kincal::cli {

namespace {

struct TrialResult {
  bool done = false;  // false: skipped after Ctrl-C, left out of every table
  TerminationType termination = TerminationType::kFailed;
  int iterations = 0;
  double parameter_rms = 0;
  double seconds = 0;
  PoseErrorStats before, after;
  std::vector<PoseErrorStats> trace;  // validation errors per iteration
};

struct CaseResult {
  PaperCase paper;
  std::vector<TrialResult> trials;
};

template <class F>
std::vector<double> collect(const std::vector<TrialResult>& trials, F field) {
  std::vector<double> v;
  v.reserve(trials.size());
  for (const auto& t : trials) v.push_back(field(t));
  return v;
}

// The trials that ran (all of them unless the run was interrupted).
std::vector<TrialResult> finished(const std::vector<TrialResult>& trials) {
  std::vector<TrialResult> out;
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

int count(const std::vector<TrialResult>& trials, TerminationType type) {
  return static_cast<int>(std::count_if(
      trials.begin(), trials.end(), [&](const TrialResult& t) { return t.termination == type; }));
}

// Mean over trials of the validation error at each iteration; a trial that stopped earlier
// contributes its final value (its model no longer changes).
std::vector<std::array<double, 2>> mean_trace(const std::vector<TrialResult>& trials) {
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

int run_reproduce(const Args& args) {
  po::options_description options("kincal reproduce");
  options.add_options()("trials", po::value<int>()->default_value(100),
                        "Monte Carlo trials (seeds) per case")(
      "threads", po::value<int>()->default_value(0), "worker threads (0 = all cores)")(
      "out", po::value<std::string>()->default_value("reproduce-out"),
      "directory for summary.csv, trials.csv and trace.csv (created with its parents)");
  add_json_option(options, "the summary per case");
  add_progress_option(options);
  add_scenario_options(options, false);
  add_solver_options(options);
  po::variables_map vm;
  if (!parse_command_line("reproduce", args, options, vm)) return 0;
  const int num_trials = vm["trials"].as<int>();
  if (num_trials < 1) throw CliError("--trials must be at least 1");
  const int threads = vm["threads"].as<int>();
  if (threads < 0 || threads > 1024) throw CliError("--threads must be from 0 to 1024");
  int unused_case = 0;
  const ScenarioOptions base = scenario_options_from(vm, &unused_case);
  const SolverChoice choice = make_solver_choice(vm);
  const std::string out_dir = vm["out"].as<std::string>();
  const auto model = make_cube_hexapod();
  const int num_cases = static_cast<int>(paper_cases().size());
  // Each trial keeps its validation errors per iteration (about 30 on these cases) and a row
  // of each table; each worker holds one scenario and its solve at a time.
  int largest_case = 0;
  for (const PaperCase& paper : paper_cases())
    largest_case = std::max(largest_case, paper.num_configurations);
  const double per_trial = num_cases * (sizeof(TrialResult) + 31 * sizeof(PoseErrorStats) + 512);
  const double per_worker =
      largest_case * (kConfigurationBytes +
                      model->num_readings() * solve_bytes_per_row(model->parameters().num_free())) +
      base.num_validation * kConfigurationBytes;
  const int workers = threads == 0 ? hardware_threads() : threads;
  // The validation set first: it is part of every worker's share in the check of --trials.
  check_memory("--validation " + std::to_string(base.num_validation), base.num_validation,
               workers * kConfigurationBytes, "pose", workers * largest_case * 4096.0);
  check_memory("--trials " + std::to_string(num_trials), num_trials, per_trial, "trial",
               workers * per_worker);
  if (static_cast<long long>(num_trials) * num_cases > std::numeric_limits<int>::max())
    throw CliError("--trials " + std::to_string(num_trials) + ": expected at most " +
                   std::to_string(std::numeric_limits<int>::max() / num_cases));
  // The directory is replaced whole at the end, so a crash leaves the old tables or the
  // new ones, never a mix.
  OutputPlan plan;
  plan.output_directory("--out", out_dir, {"summary.csv", "trials.csv", "trace.csv"});
  const std::string json_file = json_output(vm);
  if (!json_file.empty()) plan.output("--json", json_file);
  plan.check();
  const bool json_to_stdout = !json_file.empty() && plan.to_stdout("--json");

  std::vector<CaseResult> cases;
  for (const PaperCase& paper : paper_cases()) cases.push_back({paper, {}});
  for (auto& c : cases) c.trials.resize(num_trials);

  // One flat index over (trial, case) keeps all cores busy to the end; trial-major, so that
  // a run stopped by Ctrl-C has about as many trials of every case.
  const int total = num_cases * num_trials;
  Progress progress("reproduce", total, "trials", progress_wanted(vm));
  const InterruptGuard interrupt_guard("reproduce");
  parallel_for(total, threads, [&](int index) {
    if (interrupt_requested()) return;  // finish the trials under way, start no more
    CaseResult& c = cases[index % num_cases];
    const int trial = index / num_cases;
    ScenarioOptions o = base;
    o.num_configurations = c.paper.num_configurations;
    o.noise_half_width = c.paper.noise_half_width;
    o.seed = derive_seed(base.seed, static_cast<std::uint64_t>(trial));
    const Scenario scenario = make_scenario(model, o);
    const CalibrationRun run = run_calibration(scenario, *choice.solver, choice.options, true);
    TrialResult& r = c.trials[trial];
    r.termination = run.summary.termination;
    r.iterations = run.summary.iterations;
    r.parameter_rms = run.parameter_rms_error;
    r.seconds = run.solve_seconds;
    r.before = run.before;
    r.after = run.after;
    r.trace = run.trace_errors;
    r.done = true;
    progress.advance();
  });
  progress.finish();
  int trials_done = 0;
  for (const auto& c : cases)
    for (const auto& t : c.trials) trials_done += t.done;
  // A Ctrl-C after the last trial started leaves nothing out: then the results are whole.
  const bool partial = trials_done < total;

  // With --json - the table goes to stderr, so that standard output holds only the JSON.
  std::FILE* text = json_to_stdout ? stderr : stdout;
  std::fprintf(text,
               "kincal reproduce: %d trials per case, solver %s, parameter errors ±%g mm, "
               "%d validation poses%s\n",
               num_trials, choice.name.c_str(), base.param_error_half_width, base.num_validation,
               partial ? " (PARTIAL: interrupted)" : "");
  std::fprintf(text, "%-4s %-9s %5s | %-32s | %-32s | %5s | %-17s | %s\n", "case", "noise mm",
               "poses", "position error mm", "orientation error rad", "iter", "conv/maxit/div/fail",
               "unreachable");
  std::fprintf(text, "%-4s %-9s %5s | %10s %10s %10s | %10s %10s %10s | %5s | %-17s | %s\n", "", "",
               "", "before", "after", "after p90", "before", "after", "after p90", "med", "",
               "(trials)");
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
  nlohmann::ordered_json json_cases = nlohmann::ordered_json::array();
  for (const CaseResult& c : cases) {
    const std::vector<TrialResult> t = finished(c.trials);
    const auto pos_before =
        collect(t, [](const TrialResult& r) { return r.before.position_mean_mm; });
    const auto pos_after =
        collect(t, [](const TrialResult& r) { return r.after.position_mean_mm; });
    const auto ori_before =
        collect(t, [](const TrialResult& r) { return r.before.orientation_mean_rad; });
    const auto ori_after =
        collect(t, [](const TrialResult& r) { return r.after.orientation_mean_rad; });
    const auto iterations =
        collect(t, [](const TrialResult& r) { return static_cast<double>(r.iterations); });
    const auto param_rms = collect(t, [](const TrialResult& r) { return r.parameter_rms; });
    const int conv = count(t, TerminationType::kConverged);
    const int maxit = count(t, TerminationType::kMaxIterations);
    const int div = count(t, TerminationType::kDiverged);
    const int fail = count(t, TerminationType::kFailed);
    const int stopped = count(t, TerminationType::kUserStopped);
    // Validation means are over the poses the calibrated model reaches: say how many trials
    // had poses it could not reach, so that such a model does not look better than it is.
    const int unreachable = static_cast<int>(std::count_if(
        t.begin(), t.end(), [](const TrialResult& r) { return r.after.fk_failures > 0; }));
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
    std::fprintf(
        text, "%-4d %-9g %5d | %10.4g %10.4g %10.4g | %10.4g %10.4g %10.4g | %5.0f | %-17s | %d\n",
        c.paper.id, c.paper.noise_half_width, c.paper.num_configurations, stats[0], stats[2],
        stats[3], stats[4], stats[6], stats[7], stats[9], outcome, unreachable);
    summary_csv << c.paper.id << ',' << c.paper.noise_half_width << ','
                << c.paper.num_configurations << ',' << n << ',' << choice.name;
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
      const TrialResult& r = c.trials[i];
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
  plan.write_directory("--out", {{"summary.csv", summary_csv.str()},
                                 {"trials.csv", trials_csv.str()},
                                 {"trace.csv", trace_csv.str()}});
  if (!json_file.empty()) {
    nlohmann::ordered_json json = {{"format", "kincal-reproduce"},
                                   {"version", 1},
                                   {"solver", choice.name},
                                   {"trials_per_case", num_trials},
                                   {"partial", partial},
                                   {"param_error_half_width_mm", base.param_error_half_width},
                                   {"validation_poses", base.num_validation},
                                   {"seed", base.seed},
                                   {"out", out_dir},
                                   {"cases", json_cases}};
    plan.write({{"--json", json.dump(2) + "\n"}});
  }
  std::fprintf(text,
               "pose errors are means over the validation poses (before = nominal geometry); "
               "median/p90 over trials;\nunreachable = trials whose calibrated model cannot reach "
               "some validation poses (left out of their means).\n"
               "wrote %s/summary.csv, trials.csv, trace.csv (mean error per iteration: "
               "the paper's Figs. 3-4)\n",
               out_dir.c_str());
  if (partial) {
    std::fprintf(stderr,
                 "kincal reproduce: interrupted: wrote the %d of %d trials that finished, as "
                 "partial results (partial = true in %s/summary.csv%s)\n",
                 trials_done, total, out_dir.c_str(), json_file.empty() ? "" : " and --json");
    return 130;  // the shell's code for a run ended by SIGINT
  }
  return 0;
}

}  // namespace kincal::cli
