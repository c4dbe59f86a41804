#pragma once
// The paper's Monte Carlo (kincal reproduce) as functions: one trial, and the tables and JSON
// of a set of trials. The command runs the trials on threads (cli/command_reproduce.cpp), the
// Python module on a Dask cluster (python/kincal/studies.py); both give the same numbers,
// since trial t of a case is a function of (options, case, t) alone.

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "kincal/framework/calibration/simulation.hpp"

namespace kincal {

struct ReproduceTrial {
  bool done = false;  // false: skipped after Ctrl-C, left out of every table
  TerminationType termination = TerminationType::kFailed;
  int iterations = 0;
  double parameter_rms = 0;
  double seconds = 0;
  PoseErrorStats before, after;
  std::vector<PoseErrorStats> trace;  // validation errors per iteration
};

struct ReproduceCase {
  PaperCase paper;
  std::vector<ReproduceTrial> trials;  // by trial index
};

/// Trial `trial` of `paper`: the scenario of seed derive_seed(base.seed, trial) with the
/// case's noise and number of configurations, calibrated from nominal.
ReproduceTrial run_reproduce_trial(const std::shared_ptr<const MeasurementModel>& model,
                                   const ScenarioOptions& base, const PaperCase& paper, int trial,
                                   const Solver& solver, const SolverOptions& options);

/// What reproduce writes for `cases` (their finished trials): one text row per case, the
/// three CSV tables, and the JSON array of per-case summaries.
struct ReproduceTables {
  std::string text_rows;
  std::string summary_csv, trials_csv, trace_csv;
  nlohmann::ordered_json json_cases;
};
ReproduceTables reproduce_tables(const std::vector<ReproduceCase>& cases, int num_trials,
                                 bool partial, const std::string& solver_name);

/// The document of `kincal reproduce --json`.
nlohmann::ordered_json reproduce_json(const std::string& solver_name, int num_trials, bool partial,
                                      const ScenarioOptions& base, const std::string& out_dir,
                                      const nlohmann::ordered_json& json_cases);

}  // namespace kincal
