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
#include "kincal/problems/suite_runner.hpp"

namespace kincal::cli {
namespace {

using problems::SuiteCaseResult;

void print_problem_list(const std::vector<std::shared_ptr<const problems::TestProblem>>& list) {
  out() << format_text("%-40s %3s %3s  %-16s %s\n", "problem", "n", "m", "starts",
                       "published minimum");
  for (const auto& p : list) {
    std::string starts;
    for (const auto& s : problems::suite_starts(*p))
      starts += (starts.empty() ? "" : ",") + s.label + (s.evaluable ? "" : "(!)");
    out() << format_text("%-40s %3d %3d  %-16s %.6g\n", p->name().c_str(), p->num_parameters(),
                         p->num_residuals(), starts.c_str(), p->published_minimum());
  }
  out() << format_text(
      "(!) = not evaluable: the cost overflows there. Costs are 1/2 |r|^2, half the "
      "paper's f.\n");
}

nlohmann::json case_json(const SuiteCaseResult& r) {
  nlohmann::json j = {{"problem", r.problem},
                      {"start", r.start},
                      {"n", r.num_parameters},
                      {"published_minimum", r.published_minimum},
                      {"evaluable", r.evaluable}};
  if (!r.evaluable) {
    j["why_not_evaluable"] = r.why_not_evaluable;
    return j;
  }
  j["termination"] = to_string(r.summary.termination);
  j["message"] = r.summary.message;
  j["iterations"] = r.summary.iterations;
  j["residual_evaluations"] = r.summary.residual_evaluations;
  j["jacobian_evaluations"] = r.summary.jacobian_evaluations;
  j["initial_cost"] = r.summary.initial_cost;
  j["final_cost"] = r.summary.final_cost;
  j["outcome"] = problems::to_string(r.outcome);
  j["seconds"] = r.seconds;
  j["contract"] = {{"ok", r.contract.ok()}, {"violations", r.contract.violations}};
  return j;
}

std::string tally_line(const std::string& solver, const problems::SuiteTally& t) {
  char line[256];
  std::snprintf(line, sizeof line,
                "%-34s solved %3d/%d  local %2d  converged %3d  false claims %d  contract "
                "violations %d  median %.3g ms",
                solver.c_str(), t.solved, t.cases, t.published_local, t.converged, t.false_claims,
                t.violations, 1e3 * t.median_seconds);
  return line;
}

}  // namespace

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
    print_problem_list(selected);
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
    nlohmann::json entry = {{"name", name},
                            {"cases", t.cases},
                            {"solved", t.solved},
                            {"published_local", t.published_local},
                            {"converged", t.converged},
                            {"false_claims", t.false_claims},
                            {"contract_violations", t.violations},
                            {"median_seconds", t.median_seconds},
                            {"results", nlohmann::json::array()}};
    for (const auto& r : results) {
      entry["results"].push_back(case_json(r));
      if (vm.count("verbose") && r.evaluable)
        text << "  " << name << " " << r.problem << " from " << r.start << ": "
             << to_string(r.summary.termination) << ", cost " << r.summary.final_cost << " ("
             << problems::to_string(r.outcome) << ")"
             << (r.contract.ok() ? "" : " CONTRACT BROKEN: " + r.contract.report()) << "\n";
      else if (!r.contract.ok())
        text << "  " << name << " " << r.problem << " from " << r.start
             << ": CONTRACT BROKEN: " << r.contract.report() << "\n";
    }
    progress.finish();
    text << tally_line(name, t) << (t.cases < runs_per_solver ? " (PARTIAL: interrupted)" : "")
         << "\n";
    out["solvers"].push_back(entry);
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
