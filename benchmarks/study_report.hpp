#pragma once
// Summaries of the accuracy study and the files it writes.

#include <string>

#include "benchmarks/study.hpp"

namespace kincal::bench {

/// One (case, backend) cell of the study.
struct CellSummary {
  std::string case_id;
  std::string solver;
  int trials = 0;  ///< trials run (0: the backend was not run on this case)
  double parameter_rms_median = 0, parameter_rms_p90 = 0;        ///< mm
  double position_mean_median = 0, position_mean_p90 = 0;        ///< mm
  double orientation_mean_median = 0, orientation_mean_p90 = 0;  ///< rad
  double iterations_median = 0;
  double residual_evaluations_median = 0, jacobian_evaluations_median = 0;
  double seconds_median = 0, seconds_p90 = 0;
  int converged = 0, max_iterations = 0, diverged = 0, failed = 0, user_stopped = 0;
  /// Monte Carlo RMS over trials (root of the mean of squares), finite trials only.
  double mc_parameter_rms = 0, mc_position_rms = 0, mc_orientation_rms = 0;
  /// Monte Carlo RMS / Cramér-Rao RMS; NaN for a noise-free case (the bound is zero).
  double efficiency_parameters = 0, efficiency_position = 0, efficiency_orientation = 0;
};

/// The Cramér-Rao prediction of one case, averaged over its trials.
struct CaseBound {
  std::string case_id;
  double condition_number_median = 0;
  double parameter_rms = 0;    ///< sqrt(mean over trials of trace(Cov)/n), mm
  double position_rms = 0;     ///< mm
  double orientation_rms = 0;  ///< rad
};

CaseBound summarize_bound(const StudyResults& results, int case_index);
CellSummary summarize_cell(const StudyResults& results, int case_index, int solver_index);

/// Writes summary.csv, summary.json, bounds.csv, trials.csv, traces.csv and accuracy.md to
/// `directory` (created when missing).
void write_study_files(const StudyResults& results, const std::string& directory);

}  // namespace kincal::bench
