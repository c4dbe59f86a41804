// The studies' C++ side (python/kincal/studies.py drives them, in-process or on Dask): the
// trials of the paper's Monte Carlo one at a time, as plain tuples that pickle exactly, and
// the report of a set of them, made by the same functions as `kincal reproduce`
// (framework/workflows/reproduce.hpp).

#include <pybind11/stl.h>

#include <atomic>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "interrupt.hpp"
#include "kincal/framework/base/parallel.hpp"
#include "kincal/framework/io/output_files.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/framework/workflows/reproduce.hpp"
#include "kincal/framework/workflows/simulate.hpp"
#include "kincal/models/presets.hpp"

namespace kincal::python {

namespace {

// The study's settings, as typed values (a plain dict that pickles, so that it travels to
// Dask's workers as it is): the scenario through the library's scenario_options, the backend
// and its settings checked once.
struct ReproduceSetup {
  ScenarioOptions base;
  std::string solver_name;
  std::shared_ptr<const Solver> solver;
  SolverOptions options;
};

ReproduceSetup reproduce_setup(const py::dict& spec) {
  ScenarioText text;
  text.param_error = spec["param_error"].cast<std::string>();
  if (!spec["config_range"].is_none()) text.config_range = spec["config_range"].cast<std::string>();
  text.seed = spec["seed"].cast<std::uint64_t>();
  text.validation = spec["validation"].cast<int>();
  ReproduceSetup setup;
  setup.base = scenario_options(text, "");
  setup.solver_name = spec["solver"].cast<std::string>();
  setup.solver = SolverRegistry::global().create(setup.solver_name);
  setup.options.max_iterations = spec["max_iterations"].cast<int>();
  if (setup.options.max_iterations < 1)
    throw std::invalid_argument("max_iterations must be at least 1");
  setup.options.backend = setup.solver->parse_settings(
      spec["solver_option"].cast<std::map<std::string, std::string>>());
  setup.solver->check_options(setup.options);  // a trial always runs to its end: no callback
  return setup;
}

py::tuple stats_tuple(const PoseErrorStats& s) {
  return py::make_tuple(s.position_mean_mm, s.position_max_mm, s.orientation_mean_rad,
                        s.orientation_max_rad, s.fk_failures);
}

PoseErrorStats stats_from(const py::handle& h) {
  const auto t = h.cast<py::tuple>();
  PoseErrorStats s;
  s.position_mean_mm = t[0].cast<double>();
  s.position_max_mm = t[1].cast<double>();
  s.orientation_mean_rad = t[2].cast<double>();
  s.orientation_max_rad = t[3].cast<double>();
  s.fk_failures = t[4].cast<int>();
  return s;
}

TerminationType termination_from(const std::string& word) {
  for (TerminationType t :
       {TerminationType::kConverged, TerminationType::kMaxIterations, TerminationType::kDiverged,
        TerminationType::kFailed, TerminationType::kUserStopped})
    if (word == to_string(t)) return t;
  throw py::value_error("trial: unknown termination '" + word + "'");
}

py::object trial_tuple(const ReproduceTrial& r) {
  if (!r.done) return py::none();
  py::list trace;
  for (const auto& e : r.trace) trace.append(stats_tuple(e));
  return py::make_tuple(std::string(to_string(r.termination)), r.iterations, r.parameter_rms,
                        r.seconds, stats_tuple(r.before), stats_tuple(r.after), trace);
}

ReproduceTrial trial_from(const py::handle& h) {
  ReproduceTrial r;
  if (h.is_none()) return r;
  const auto t = h.cast<py::tuple>();
  if (t.size() != 7) throw py::value_error("trial: expected a tuple of 7 from reproduce_trials");
  r.done = true;
  r.termination = termination_from(t[0].cast<std::string>());
  r.iterations = t[1].cast<int>();
  r.parameter_rms = t[2].cast<double>();
  r.seconds = t[3].cast<double>();
  r.before = stats_from(t[4]);
  r.after = stats_from(t[5]);
  for (const auto& e : t[6].cast<py::list>()) r.trace.push_back(stats_from(e));
  return r;
}

// Runs the (case index, trial) pairs on `threads` threads with the GIL released; a pair not
// started before Ctrl-C is None.
py::list reproduce_trials(const py::dict& spec, const std::vector<std::pair<int, int>>& tasks,
                          int threads, bool catch_sigint) {
  const ReproduceSetup setup = reproduce_setup(spec);
  const auto& cases = paper_cases();
  for (const auto& [case_index, trial] : tasks)
    if (case_index < 0 || case_index >= static_cast<int>(cases.size()) || trial < 0)
      throw py::value_error("tasks: (case index, trial) out of range: (" +
                            std::to_string(case_index) + ", " + std::to_string(trial) + ")");
  const std::shared_ptr<const MeasurementModel> model = make_cube_hexapod();
  std::vector<ReproduceTrial> results(tasks.size());
  {
    py::gil_scoped_release release;
    SigintScope sigint(catch_sigint);
    parallel_for(static_cast<int>(tasks.size()), threads, [&](int i) {
      if (sigint_received()) return;  // as the program: finish the trials under way
      const auto& [case_index, trial] = tasks[i];
      results[i] = run_reproduce_trial(model, setup.base, cases[case_index], trial, *setup.solver,
                                       setup.options);
    });
  }
  py::list out;
  for (const auto& r : results) out.append(trial_tuple(r));
  return out;
}

// results[case index][trial]: a tuple from reproduce_trials, or None (not run).
py::tuple reproduce_report(const py::dict& spec, int num_trials, const py::list& results,
                           const std::string& out_dir) {
  const ReproduceSetup setup = reproduce_setup(spec);
  const auto& paper = paper_cases();
  if (results.size() != paper.size())
    throw py::value_error("results: expected one list per case (" + std::to_string(paper.size()) +
                          ")");
  std::vector<ReproduceCase> cases;
  bool partial = false;
  for (std::size_t c = 0; c < paper.size(); ++c) {
    ReproduceCase rc{paper[c], {}};
    const auto trials = results[c].cast<py::list>();
    if (static_cast<int>(trials.size()) != num_trials)
      throw py::value_error("results: expected " + std::to_string(num_trials) + " trials per case");
    for (const auto& t : trials) {
      rc.trials.push_back(trial_from(t));
      partial = partial || !rc.trials.back().done;
    }
    cases.push_back(std::move(rc));
  }
  const ReproduceTables tables = reproduce_tables(cases, num_trials, partial, setup.solver_name);
  const nlohmann::ordered_json json = reproduce_json(setup.solver_name, num_trials, partial,
                                                     setup.base, out_dir, tables.json_cases);
  return py::make_tuple(json.dump(2) + "\n", tables.text_rows, tables.summary_csv,
                        tables.trials_csv, tables.trace_csv);
}

// reproduce's out directory: the program's rule (framework/io/output_files.hpp, docs/reliability.md
// "A directory: replaced in one step"). It may hold only the three tables, is checked before
// the work and again just before it is swapped, whole, with the new one.
const std::vector<std::string> kReproduceTables = {"summary.csv", "trials.csv", "trace.csv"};

DirectoryTarget reproduce_directory(const std::string& path, const std::string& what) {
  return resolve_output_directory(path, what + " '" + path + "'", kReproduceTables);
}

void write_reproduce_directory(const std::string& path, const std::string& summary,
                               const std::string& trials, const std::string& trace) {
  const DirectoryTarget target = reproduce_directory(path, "cannot write out");
  py::gil_scoped_release release;
  write_directory_atomically(
      target, {{"summary.csv", summary}, {"trials.csv", trials}, {"trace.csv", trace}});
}

}  // namespace

void bind_studies(py::module_& m) {
  m.def(
      "check_reproduce_directory",
      [](const std::string& path) { reproduce_directory(path, "out"); }, py::arg("path"),
      "Raises OutputError (a ValueError) unless `path` may be reproduce's out directory: a new "
      "directory, or one holding only summary.csv, trials.csv and trace.csv (it is replaced "
      "whole), not the current directory or a parent of it, the root or a mount point.");
  m.def("write_reproduce_directory", &write_reproduce_directory, py::arg("path"),
        py::arg("summary"), py::arg("trials"), py::arg("trace"),
        "Replaces directory `path` by one holding the three tables, in one step (renameat2 "
        "RENAME_EXCHANGE), as `kincal reproduce --out` does; checked again first.");
  m.def("reproduce_trials", &reproduce_trials, py::arg("spec"), py::arg("tasks"),
        py::arg("threads") = 0, py::arg("catch_sigint") = false,
        "Trials of the paper's Monte Carlo: `spec` the study's settings (solver, seed, "
        "validation, param_error, config_range, max_iterations, solver_option), `tasks` "
        "(case index 0..4, trial) pairs. Returns one plain tuple per "
        "task (None when Ctrl-C came first). The GIL is released.");
  m.def("reproduce_report", &reproduce_report, py::arg("spec"), py::arg("trials"),
        py::arg("results"), py::arg("out"),
        "The report of reproduce_trials' results, per case and trial: (JSON text as "
        "`kincal reproduce --json` writes it, text rows, summary.csv, trials.csv, trace.csv).");
}

}  // namespace kincal::python
