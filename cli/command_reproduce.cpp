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
#include "kincal/cli/console.hpp"
#include "kincal/cli/interrupt.hpp"
#include "kincal/cli/memory_check.hpp"
#include "kincal/cli/progress.hpp"
#include "kincal/cli/project_record.hpp"
#include "kincal/cli/shared_options.hpp"
#include "kincal/cli/simulation_report.hpp"
#include "kincal/framework/base/parallel.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/base/statistics.hpp"
#include "kincal/framework/workflows/reproduce.hpp"
#include "kincal/models/presets.hpp"

namespace kincal::cli {

int run_reproduce(const Args& args) {
  po::options_description options("kincal reproduce");
  options.add_options()("trials", po::value<int>()->default_value(100),
                        "Monte Carlo trials (seeds) per case")(
      "out", po::value<std::string>()->default_value("reproduce-out"),
      "directory for summary.csv, trials.csv and trace.csv (created with its parents)");
  add_json_option(options, "the summary per case");
  add_progress_option(options);
  add_scenario_options(options, false);
  add_solver_options(options);
  add_threads_option(options);
  po::variables_map vm;
  if (!parse_command_line("reproduce", args, options, vm)) return 0;
  const int num_trials = vm["trials"].as<int>();
  if (num_trials < 1) throw CliError("--trials must be at least 1");
  const int threads = threads_option(vm);
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
  const double per_trial = num_cases * (sizeof(ReproduceTrial) + 31 * sizeof(PoseErrorStats) + 512);
  const double per_worker =
      largest_case * (kConfigurationBytes +
                      model->num_readings() * solve_bytes_per_row(model->parameters().num_free())) +
      base.num_validation * kConfigurationBytes;
  const int workers = threads;
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
  OutputPlan plan(console_output());
  plan.output_directory("--out", out_dir, {"summary.csv", "trials.csv", "trace.csv"});
  const std::string json_file = json_output(vm);
  if (!json_file.empty()) plan.output("--json", json_file);
  plan.check();
  const bool json_to_stdout = !json_file.empty() && plan.to_stdout("--json");

  std::vector<ReproduceCase> cases;
  for (const PaperCase& paper : paper_cases()) cases.push_back({paper, {}});
  for (auto& c : cases) c.trials.resize(num_trials);

  // One flat index over (trial, case) keeps all cores busy to the end; trial-major, so that
  // a run stopped by Ctrl-C has about as many trials of every case.
  const int total = num_cases * num_trials;
  Progress progress("reproduce", total, "trials", progress_wanted(vm));
  const InterruptGuard interrupt_guard("reproduce");
  parallel_for(total, threads, [&](int index) {
    if (interrupt_requested()) return;  // finish the trials under way, start no more
    ReproduceCase& c = cases[index % num_cases];
    const int trial = index / num_cases;
    c.trials[trial] =
        run_reproduce_trial(model, base, c.paper, trial, *choice.solver, choice.options);
    progress.advance();
  });
  progress.finish();
  int trials_done = 0;
  for (const auto& c : cases)
    for (const auto& t : c.trials) trials_done += t.done;
  // A Ctrl-C after the last trial started leaves nothing out: then the results are whole.
  const bool partial = trials_done < total;

  // With --json - the table goes to stderr, so that standard output holds only the JSON.
  std::ostream& text = json_to_stdout ? err() : out();
  text << format_text(
      "kincal reproduce: %d trials per case, solver %s, parameter errors ±%g mm, "
      "%d validation poses%s\n",
      num_trials, choice.name.c_str(), base.param_error_for(kMillimetre), base.num_validation,
      partial ? " (PARTIAL: interrupted)" : "");
  text << format_text("%-4s %-9s %5s | %-32s | %-32s | %5s | %-17s | %s\n", "case", "noise mm",
                      "poses", "position error mm", "orientation error rad", "iter",
                      "conv/maxit/div/fail", "unreachable");
  text << format_text("%-4s %-9s %5s | %10s %10s %10s | %10s %10s %10s | %5s | %-17s | %s\n", "",
                      "", "", "before", "after", "after p90", "before", "after", "after p90", "med",
                      "", "(trials)");
  const ReproduceTables tables = reproduce_tables(cases, num_trials, partial, choice.name);
  text << tables.text_rows;
  plan.write_directory("--out", {{"summary.csv", tables.summary_csv},
                                 {"trials.csv", tables.trials_csv},
                                 {"trace.csv", tables.trace_csv}});
  if (!json_file.empty()) {
    const nlohmann::ordered_json json =
        reproduce_json(choice.name, num_trials, partial, base, out_dir, tables.json_cases);
    plan.write({{"--json", json_report_text(json)}});
  }
  text << format_text(
      "pose errors are means over the validation poses (before = nominal geometry); "
      "median/p90 over trials;\nunreachable = trials whose calibrated model cannot reach "
      "some validation poses (left out of their means).\n"
      "wrote %s/summary.csv, trials.csv, trace.csv (mean error per iteration: "
      "the paper's Figs. 3-4)\n",
      out_dir.c_str());
  if (partial) {
    err() << format_text(
        "kincal reproduce: interrupted: wrote the %d of %d trials that finished, as "
        "partial results (partial = true in %s/summary.csv%s)\n",
        trials_done, total, out_dir.c_str(), json_file.empty() ? "" : " and --json");
    return 130;  // the shell's code for a run ended by SIGINT
  }
  return 0;
}

}  // namespace kincal::cli
