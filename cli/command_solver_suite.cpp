// kincal solver-suite: backends on the Moré-Garbow-Hillstrom test suite (problems/), each solve
// checked against the honesty contract (docs/solvers.md). Exit code 1 when a contract was
// broken, so that scripts can use it as a check.

#include <chrono>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "kincal/cli/cli_util.hpp"
#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/interrupt.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/cli/progress.hpp"
#include "kincal/framework/io/output_plan.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/problems/mgh_problems.hpp"
#include "kincal/problems/suite_report.hpp"
#include "kincal/problems/suite_runner.hpp"

namespace kincal::cli {

int run_solver_suite(const Args& args) {
  po::options_description options("kincal solver-suite");
  options.add_options()("solver", po::value<std::vector<std::string>>()->composing(),
                        "backend to run (repeatable; default: every featured backend)")(
      "problem", po::value<std::string>()->default_value("*"),
      "problems whose name matches (glob with * and ?, or a part of the name)")(
      "solver-option", po::value<std::vector<std::string>>()->composing(),
      "backend setting key=value (repeatable; needs a single --solver)")(
      "max-iterations", po::value<int>(),
      "iteration limit (default: 200; NLopt: 200 (n + 1) objective evaluations)")(
      "list", "list the problems with their sizes, starts and published minima, and exit")(
      "verbose,v", "print one line per problem and start");
  add_json_option(options, "every result");
  add_progress_option(options);
  po::variables_map vm;
  if (!parse_command_line("solver-suite", args, options, vm)) return 0;

  const auto selected = problems::select_problems(vm["problem"].as<std::string>());
  if (vm.count("list")) {
    out() << problems::problem_list_text(selected);
    return 0;
  }
  const auto& registry = SolverRegistry::global();
  std::vector<std::string> solvers;
  if (vm.count("solver")) {
    solvers = vm["solver"].as<std::vector<std::string>>();
  } else {
    solvers = registry.featured_names();
  }
  if (vm.count("solver-option") && solvers.size() != 1)
    throw CliError("--solver-option needs exactly one --solver (each backend has its own keys)");
  if (vm.count("max-iterations")) check_max_iterations(vm["max-iterations"].as<int>());
  // Names and options are checked before any work; the settings are parsed once, here.
  SolverOptions overrides;
  for (const auto& name : solvers) {
    try {
      const std::unique_ptr<Solver> solver = registry.create(name);
      if (vm.count("solver-option"))
        overrides.backend = solver->parse_settings(
            parse_key_values(vm["solver-option"].as<std::vector<std::string>>(), "solver-option"));
      solver->check_options(overrides);
    } catch (const InvalidSolverOptions& e) {
      throw CliError(e.what());
    }
  }
  const bool json = vm.count("json") > 0;
  OutputPlan plan(console_output());
  if (json) plan.output("--json", vm["json"].as<std::string>());
  plan.check();
  const bool json_to_stdout = json && plan.to_stdout("--json");

  nlohmann::json out = {{"format", "kincal-solver-suite"},
                        {"version", 1},
                        {"problems", selected.size()},
                        {"solvers", nlohmann::json::array()}};
  std::ostream& text = json_to_stdout ? err() : cli::out();  // `out` is the JSON here
  int broken = 0;
  long runs_per_solver = 0;
  for (const auto& p : selected)
    for (const auto& start : problems::suite_starts(*p)) runs_per_solver += start.evaluable;
  Progress progress("solver-suite", runs_per_solver * static_cast<long>(solvers.size()), "runs",
                    progress_wanted(vm));
  // Ctrl-C: the problem under way finishes, the rest are skipped, what finished is written
  // (marked partial) and the exit code is 130.
  const InterruptGuard interrupt_guard("solver-suite");
  bool partial = false;
  long finished = 0;
  // The time left weighs each backend by its own speed (ipopt takes many times what gn
  // does): per-run durations, backend by backend, for staged_time_left.
  std::vector<std::vector<double>> durations;
  using Clock = std::chrono::steady_clock;
  Clock::time_point run_start;
  const auto run_done = [&] {
    const Clock::time_point now = Clock::now();
    durations.back().push_back(std::chrono::duration<double>(now - run_start).count());
    run_start = now;
    progress.advance(
        1, staged_time_left(durations, runs_per_solver, static_cast<int>(solvers.size())));
  };
  for (const auto& name : solvers) {
    if (interrupt_requested()) {
      partial = true;
      break;
    }
    durations.emplace_back();
    run_start = Clock::now();
    // configure() is called as each run starts: the one before it is done.
    bool started = false;
    const auto configure = [&](SolverOptions& o) {
      if (started) run_done();
      started = true;
      if (overrides.backend) o.backend = overrides.backend;
      if (vm.count("max-iterations")) o.max_iterations = vm["max-iterations"].as<int>();
    };
    std::vector<problems::SuiteCaseResult> results;
    for (const auto& problem : selected) {
      if (interrupt_requested()) {
        partial = true;
        break;
      }
      const auto runs = problems::run_suite(name, {problem}, configure);
      results.insert(results.end(), runs.begin(), runs.end());
    }
    if (started) run_done();
    const problems::SuiteTally t = problems::tally(results);
    finished += t.cases;
    broken += t.violations;
    out["solvers"].push_back(problems::suite_json(name, t, results));
    for (const auto& r : results) text << problems::case_line(name, r, vm.count("verbose") > 0);
    progress.finish();
    text << problems::tally_line(name, t)
         << (t.cases < runs_per_solver ? " (PARTIAL: interrupted)" : "") << "\n";
  }
  out["partial"] = partial;
  if (!vm.count("solver")) {
    out["skipped"] = nlohmann::json::array();
    for (const auto& missing : registry.unavailable()) {
      text << missing.name << ": skipped, " << missing.reason << "\n";
      out["skipped"].push_back({{"name", missing.name}, {"reason", missing.reason}});
    }
  }
  if (json) plan.write({{"--json", out.dump(2) + "\n"}});
  if (partial) {
    err() << format_text(
        "kincal solver-suite: interrupted: %ld of %ld runs finished; the tallies%s "
        "cover those only\n",
        finished, runs_per_solver * static_cast<long>(solvers.size()),
        json ? " and the JSON (\"partial\": true)" : "");
    return 130;  // the shell's code for a run ended by SIGINT
  }
  return broken > 0 ? 1 : 0;
}

}  // namespace kincal::cli
