#pragma once
// Solving a calibration in the chosen formulation: nested (forward kinematics inside every
// residual, the paper's) or implicit (the poses as unknowns, closure constraints as residuals:
// framework/calibration/implicit_calibration_problem.hpp). What comes back is the nested problem's
// in both: x its free parameters, the Summary its cost and verdict at x, so that every report reads
// the same quantities. A combination the implicit formulation does not handle (an open chain, a
// prior, parameter-only constraints, a backend without it, backend options) is solved nested, and
// `note` says so. The nested problem includes the model's parameter-only constraints
// (constrained_problem.hpp) and the prior. An implicit solve that fails or diverges is followed
// by the nested solve from the same start, whose result is returned: `note` says so and
// `failed_implicit` keeps the implicit solve's summary.

#include <optional>
#include <string>

#include "kincal/framework/calibration/calibration_problem.hpp"
#include "kincal/framework/calibration/prior_problem.hpp"
#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

enum class Formulation { kNested, kImplicit };

/// "nested" or "implicit".
const char* to_string(Formulation formulation);
/// Throws std::invalid_argument naming the value unless it is "nested" or "implicit".
Formulation parse_formulation(const std::string& text);
/// Nested for every mechanism today: for a serial arm forward kinematics is explicit, and
/// for a closed chain the implicit formulation measured 1.2-1.3 times faster on the paper's
/// cases but slower from m = 6000 configurations and over 1 GB at 10^6 (docs/benchmarks.md),
/// short of what would justify moving every documented result by the up to 3e-4 mm by which
/// the two end points differ.
Formulation default_formulation(const MeasurementModel& model);

struct CalibrationSolve {
  Summary summary;
  Formulation formulation = Formulation::kNested;  ///< the one that was solved
  std::string note;                                ///< why the requested one was not, or empty
  /// The implicit solve's summary when it ended failed or diverged and the nested solve from
  /// the same start replaced it (summary is then the nested solve's alone, its times and
  /// counts included; each solve had the options' iteration limit).
  std::optional<Summary> failed_implicit;
};

/// Solves `problem` (the MAP problem when `prior` has any entry) from x, in `requested` when
/// it applies; x holds the estimate on return.
CalibrationSolve solve_calibration(const Solver& solver, const CalibrationProblem& problem,
                                   const Prior& prior, VectorXd& x, const SolverOptions& options,
                                   Formulation requested);

}  // namespace kincal
