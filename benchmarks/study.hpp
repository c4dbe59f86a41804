#pragma once
// The accuracy and robustness study: every case x every backend, as a Monte Carlo over seeds
// in which trial t of a case draws one scenario that every backend then solves.

#include <cstdint>
#include <string>
#include <vector>

#include "benchmarks/cramer_rao.hpp"
#include "kincal/framework/calibration/simulation.hpp"

namespace kincal::bench {

struct StudyCase {
  std::string id;            ///< "1".."5" (Table 2), "3e20", "m300"
  std::string description;   ///< one line for tables
  ScenarioOptions scenario;  ///< the seed is set per trial
  bool paper = false;        ///< a Table 2 case (per-iteration tracking for Figs. 3/4)
};

/// Table 2's five cases, then the harder ones: case 3 with +-20 mm parameter errors, and 300
/// configurations with the paper's largest noise (a = 0.0125 mm).
std::vector<StudyCase> all_cases(int num_validation);

struct StudyOptions {
  int trials = 200;
  std::uint64_t seed = 1;
  int threads = 0;  ///< 0 = all cores
  int validation = 50;
  std::vector<std::string> cases;    ///< case ids; empty = all
  std::vector<std::string> solvers;  ///< registry names; empty = every featured name
  /// Solvers whose per-iteration validation errors are recorded on Table 2 cases.
  std::vector<std::string> tracked_solvers = {"gn", "lm"};
  int max_iterations = 200;
  /// NLopt counts objective evaluations against max_iterations: its own budgets.
  int nlopt_gradient_evaluations = 2000;
  int nlopt_derivative_free_evaluations = 10000;
  /// Derivative-free NLopt algorithms ("nlopt:LN_*") need thousands of evaluations: they run
  /// on these cases only, and on the first `limited_trials` trials.
  std::vector<std::string> derivative_free_cases = {"1"};
  /// Gradient-based NLopt needs ~1000 evaluations: on these (large) cases it runs on the first
  /// `limited_trials` trials only.
  std::vector<std::string> nlopt_limited_cases = {"m300"};
  int limited_trials = 20;
  /// Featured names left out when `solvers` is empty.
  std::vector<std::string> excluded_solvers;
  bool progress = true;
};

/// What one backend did on one trial.
struct TrialRecord {
  bool ran = false;
  TerminationType termination = TerminationType::kFailed;
  int iterations = 0;
  int residual_evaluations = 0;
  int jacobian_evaluations = 0;
  double solve_seconds = 0;
  double parameter_rms = 0;           ///< RMS over free parameters of estimate - truth, mm
  double position_mean = 0;           ///< mean over validation poses, mm
  double orientation_mean = 0;        ///< rad
  double position_rms = 0;            ///< RMS over validation poses, mm
  double orientation_rms = 0;         ///< rad
  std::vector<PoseErrorStats> trace;  ///< per iteration, tracked solvers only
};

struct StudyResults {
  StudyOptions options;
  std::vector<StudyCase> cases;
  std::vector<std::string> solvers;
  std::vector<std::vector<CramerRaoPrediction>> cramer_rao;   ///< [case][trial]
  std::vector<std::vector<std::vector<TrialRecord>>> trials;  ///< [case][solver][trial]
  double wall_seconds = 0;
};

bool is_derivative_free(const std::string& solver);
/// Whether the study runs `solver` on `study_case`.
bool runs_on(const StudyOptions& options, const std::string& solver, const StudyCase& study_case,
             int trial);

/// Throws std::invalid_argument for unknown case ids or solver names.
StudyResults run_study(const StudyOptions& options);

}  // namespace kincal::bench
