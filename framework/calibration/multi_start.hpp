#pragma once
// Several starts of one least-squares problem (calibrate and simulate --starts): a solver that
// converged has found *a* minimum, and from far starts the hexapod's calibration has others
// whose residuals are as small as the noise (docs/benchmarks.md, "Local minima"), so only
// solving from other starting values tells them apart. Start 0 is the given x; start k >= 1
// draws each parameter around it from its spread with its own sub-stream derive_seed(seed, k),
// so the starts, and the minima found, do not depend on the number of threads.

#include <cstdint>
#include <string>
#include <vector>

#include "kincal/framework/calibration/calibration_problem.hpp"
#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

/// Where starts are drawn, per parameter of the problem (in its units): uniform in
/// x0 +- half_width where half_width > 0, else Gaussian of std `std` where std > 0, else x0.
struct StartSpread {
  VectorXd half_width;
  VectorXd std;
  /// Whether some spread is an assumed default (the model states no tolerance for it).
  bool assumed = false;
  /// The standard deviation of each parameter's draw (half_width / sqrt 3 or std; 0 = none):
  /// the scale of parameter distances.
  VectorXd scale() const;
};

/// The spread of a model's free parameters: the model file's param_error (uniform), else
/// prior_std (Gaussian), else the given half-width per unit (uniform; `assumed` is set).
StartSpread model_start_spread(const MeasurementModel& model, const std::vector<int>& free_indices,
                               double default_half_width_mm, double default_half_width_rad);

struct MultiStartOptions {
  int starts = 1;
  std::uint64_t seed = 1;
  int threads = 0;  ///< 0 = all cores
  StartSpread spread;
};

/// Two solutions are one minimum when their parameters differ by less than this many
/// spreads (RMS of the differences over StartSpread::scale) and their costs by less than
/// kSameCostRelative of the larger plus kSameCostFloor of the cost at start 0 (a noise-free
/// fit ends anywhere below the cost's rounding error).
constexpr double kSameMinimumDistance = 1e-3;
constexpr double kSameCostRelative = 1e-6;
constexpr double kSameCostFloor = 1e-12;

struct StartOutcome {
  VectorXd start;  ///< where the solve started
  VectorXd x;      ///< where it ended
  Summary summary;
  int minimum = -1;  ///< index into MultiStartResult::minima; -1 when the solve did not end
                     ///< at a solution (diverged, failed)
};

/// One distinct minimum: the lowest cost of the starts that ended there.
struct DistinctMinimum {
  double cost = 0;
  VectorXd x;
  std::vector<int> starts;      ///< the starts that ended here, ascending
  double distance_to_best = 0;  ///< RMS of (x - best x) / spread scale
};

struct MultiStartResult {
  std::vector<StartOutcome> starts;
  /// Ascending cost; minima[0] is the best.
  std::vector<DistinctMinimum> minima;
  /// The first start (lowest index) that ended at the best minimum: the estimate is its
  /// solution (0 when none reached a solution).
  int best_start = 0;
  int unsolved = 0;  ///< starts that diverged or failed
  /// The options' callback asked to stop: every start stopped at its next iteration (those
  /// not begun, at their first), and the estimate is the best of what they had reached.
  bool stopped = false;

  /// The summary the estimate is reported with: the best start's, ending "user_stopped"
  /// when the starts were stopped, even if that start had converged (the others were cut
  /// short, so it is not the best of all the starts asked for).
  Summary estimate_summary() const;
};

/// Whether a solve ended at a solution: converged, or stopped at its iteration limit.
bool reached_solution(const Summary& summary);

/// The drawn starting point of start k (k = 0: x0 itself). Throws std::invalid_argument when
/// the spread's sizes differ from x0's.
VectorXd draw_start(const VectorXd& x0, const StartSpread& spread, std::uint64_t seed, int k);

/// Solves `problem` from options.starts starting points in parallel (each solve single-threaded),
/// then groups the solutions into distinct minima. Backends that are not thread-safe (ipopt) run
/// one start at a time. The options' callback is called for every start's iterations, one call
/// at a time (records of different starts interleave); when it returns kStop, every start
/// stops. Throws std::invalid_argument when starts < 1 or the spread does not fit x0.
MultiStartResult solve_multi_start(const LeastSquaresProblem& problem, const Solver& solver,
                                   const VectorXd& x0, const SolverOptions& options,
                                   const MultiStartOptions& multi);

/// What a calibration's starts found, with where they were drawn from (`spread_from`, in
/// words): the "starts" of a calibration's result and report.
struct StartsReport {
  MultiStartResult result;
  std::uint64_t seed = 1;
  std::string spread_from;
  bool spread_assumed = false;
};

/// The report of a single solve from x0 to x.
StartsReport single_start_report(const VectorXd& x0, const VectorXd& x, const Summary& summary,
                                 std::uint64_t seed);

}  // namespace kincal
