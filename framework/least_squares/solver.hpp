#pragma once
// The Solver interface shared by every backend: one options struct, one summary.

#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "kincal/framework/least_squares/backend_settings.hpp"
#include "kincal/framework/least_squares/least_squares_problem.hpp"
#include "kincal/framework/least_squares/robust_loss.hpp"

namespace kincal {

class ImplicitCalibrationProblem;

/// Why a solve stopped. Numerical outcomes are values here, never exceptions.
enum class TerminationType {
  kConverged,      ///< a convergence test fired (see Summary::message for which)
  kMaxIterations,  ///< iteration (or evaluation) limit reached first
  kDiverged,       ///< the iterates ran away, or left the region where residuals exist
  kFailed,         ///< could not proceed: residuals not computable at the start, a backend error
  kUserStopped,    ///< the iteration callback asked to stop
};

/// Lower-case words used in reports and JSON: "converged", "max_iterations", ...
const char* to_string(TerminationType type);

struct IterationRecord {
  int iteration = 0;         ///< 0 = the initial point
  double cost = 0;           ///< 1/2 |r|^2 at the accepted iterate
  double gradient_norm = 0;  ///< max-norm of J^T r (0 when the backend does not know it)
  double step_norm = 0;      ///< |dx| of the step that led here (0 at iteration 0)
  double damping = 0;        ///< LM lambda / trust-region radius, backend-specific
  double seconds = 0;        ///< wall time since the solve started
};

enum class CallbackAction { kContinue, kStop };
/// Called after iteration 0 and after every accepted iterate, with the current x.
using IterationCallback = std::function<CallbackAction(const IterationRecord&, const VectorXd&)>;

struct SolverOptions {
  /// Upper bound on iterations (outer iterations for every backend; NLopt counts
  /// objective evaluations, see docs/solvers.md); at least 1, or check_options throws
  /// InvalidSolverOptions. 200: lm needs up to ~100 on the paper's
  /// noisiest cases (1 in ~1000 seeds), where a long curved valley leads to the minimum.
  int max_iterations = 200;
  /// Converged when |cost_old - cost_new| <= function_tolerance * cost_old.
  double function_tolerance = 1e-12;
  /// Converged when |dx| <= parameter_tolerance * (|x| + parameter_tolerance).
  double parameter_tolerance = 1e-10;
  /// Converged when every live parameter's |(J^T r)_j| <= gradient_tolerance |J_j| |r|: relative,
  /// so that a common scale of the residuals changes nothing (docs/solvers.md, "Scale").
  double gradient_tolerance = 1e-12;
  /// 0 = silent; 1 = one line per iteration on stderr; backends may print more above 1.
  int verbosity = 0;
  /// Threads used to evaluate residuals and Jacobians of large problems.
  int num_threads = 1;
  /// Optional box constraints on x (both or neither); honoured by backends that can.
  std::optional<VectorXd> lower_bounds;
  std::optional<VectorXd> upper_bounds;
  /// Observer of the iterations; may stop the solve.
  IterationCallback callback;
  /// A robust loss for data with outliers (robust_loss.hpp); backends that cannot take one
  /// (takes_robust_loss() false) reject anything but none in check_options.
  RobustLoss loss;
  /// The backend's own settings (its typed struct, e.g. LevenbergMarquardtSettings, or
  /// Solver::parse_settings of key=value text); null = the backend's defaults. A backend
  /// rejects settings that are another backend's or not valid (validity_error()).
  std::shared_ptr<const BackendSettings> backend;
};

struct Summary {
  std::string solver;  ///< registry name, e.g. "gn", "nlopt:LD_LBFGS"
  TerminationType termination = TerminationType::kFailed;
  std::string message;   ///< which test fired, or why it failed
  int backend_code = 0;  ///< the backend's own status code, for the curious
  double initial_cost = 0;
  double final_cost = 0;
  int iterations = 0;
  int residual_evaluations = 0;
  int jacobian_evaluations = 0;
  double wall_seconds = 0;
  std::vector<IterationRecord> trace;

  bool converged() const { return termination == TerminationType::kConverged; }
  /// One line: "gn: converged (relative cost change ...) after 7 iterations, cost 1e-3 -> 2e-9".
  std::string brief_report() const;
};

class Solver {
 public:
  virtual ~Solver() = default;
  /// Registry name of this instance.
  virtual std::string name() const = 0;
  /// Throws InvalidSolverOptions naming the offending setting or value.
  virtual void check_options(const SolverOptions& options) const;
  /// This backend's settings at their defaults (NoBackendSettings for one without any).
  virtual std::unique_ptr<BackendSettings> default_settings() const;
  /// Settings from key=value text, parsed and checked once at the edge (the command line,
  /// Python): the defaults with each key set. Throws InvalidSolverOptions "<name>: ...".
  std::shared_ptr<const BackendSettings> parse_settings(
      const std::map<std::string, std::string>& text) const;
  /// The settings a solve with `options` uses: options.backend, else the defaults. What the
  /// reports list as in force.
  std::shared_ptr<const BackendSettings> settings_in_force(const SolverOptions& options) const;
  /// Whether the backend minimises a robust cost (SolverOptions::loss).
  virtual bool takes_robust_loss() const { return false; }
  /// Minimises 1/2 |r(x)|^2 starting from x, which holds the result on return (the best
  /// point the backend reached). Throws only InvalidSolverOptions.
  virtual Summary solve(const LeastSquaresProblem& problem, VectorXd& x,
                        const SolverOptions& options) const = 0;
  /// Whether solve_implicit is implemented (with these options): the backends that are not
  /// fall back to the nested formulation (framework/calibration/calibration_solve.hpp says so).
  virtual bool solves_implicit(const SolverOptions&) const { return false; }
  /// Solves the implicit-loop formulation of a calibration; x holds the nested problem's free
  /// parameters, and the Summary is the nested problem's at the returned x
  /// (solvers/schur_levenberg_marquardt.hpp). Only when solves_implicit(options).
  virtual Summary solve_implicit(const ImplicitCalibrationProblem& problem, VectorXd& x,
                                 const SolverOptions& options) const;

 protected:
  /// Throws InvalidSolverOptions unless x has one entry per parameter of `problem` and the
  /// bounds, when given, have that size too with lower <= upper everywhere.
  void check_sizes(const LeastSquaresProblem& problem, const VectorXd& x,
                   const SolverOptions& options) const;
};

/// The settings of `options` that differ from their defaults, as "key value" text in order:
/// the shared ones (max_iterations, tolerances, loss, bounds) then the backend's. Not the
/// threads: they do not change the result (fixed chunks, base/parallel.hpp), and a report
/// should read the same on any machine. What a text report lists (its JSON lists every one).
std::vector<std::string> changed_settings(const SolverOptions& options);

/// A backend's settings of type S from `options` (its defaults when none are given), checked:
/// throws InvalidSolverOptions when they are another backend's or not valid.
template <class S>
S settings_for(const std::string& solver, const SolverOptions& options) {
  if (!options.backend) return S{};
  const S* settings = dynamic_cast<const S*>(options.backend.get());
  if (!settings)
    throw InvalidSolverOptions(solver + ": the backend settings given are another solver's");
  const std::string error = settings->validity_error();
  if (!error.empty()) throw InvalidSolverOptions(solver + ": " + error);
  return *settings;
}

}  // namespace kincal
