#include "kincal/solvers/nlopt_solver.hpp"

#include <nlopt.hpp>

#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <mutex>

#include "kincal/solvers/solver_common.hpp"

namespace kincal {
namespace {

// Every name NLopt knows, in enum order ("GN_DIRECT", ..., "LD_LBFGS", ...).
std::vector<std::string> all_algorithm_names() {
  std::vector<std::string> names;
  for (int a = 0; a < NLOPT_NUM_ALGORITHMS; ++a)
    names.emplace_back(nlopt_algorithm_to_string(static_cast<nlopt_algorithm>(a)));
  return names;
}

// -1 when `name` is not an NLopt algorithm. Exact, case-sensitive match.
int find_algorithm(const std::string& name) {
  const auto names = all_algorithm_names();
  for (int a = 0; a < static_cast<int>(names.size()); ++a)
    if (names[a] == name) return a;
  return -1;
}

// NLopt's naming: [G|L][N|D]_... = global/local, derivative-free/derivative-based.
bool is_global(const std::string& name) { return name[0] == 'G'; }
bool uses_derivatives(const std::string& name) { return name.size() > 1 && name[1] == 'D'; }
// Algorithms that run a subsidiary optimiser; the un-prefixed ones require us to set it.
bool takes_local_optimizer(const std::string& name) {
  return name.find("AUGLAG") != std::string::npos || name.find("MLSL") != std::string::npos;
}
bool requires_local_optimizer(const std::string& name) {
  return name == "AUGLAG" || name == "AUGLAG_EQ" || name == "G_MLSL" || name == "G_MLSL_LDS";
}

const char* kDefaultLocalAlgorithm = "LD_LBFGS";

// f = |x|^2 on [-1, 1]^2, for the probe below.
double probe_objective(unsigned n, const double* x, double* grad, void*) {
  double f = 0;
  for (unsigned i = 0; i < n; ++i) {
    f += x[i] * x[i];
    if (grad != nullptr) grad[i] = 2 * x[i];
  }
  return f;
}

// One short run of `algorithm` on the probe objective, set up as configure() would (bounds,
// subsidiary optimiser, xtol_abs).
nlopt_result probe(nlopt_algorithm algorithm) {
  nlopt_opt opt = nlopt_create(algorithm, 2);
  const double lower[2] = {-1, -1}, upper[2] = {1, 1};
  nlopt_set_lower_bounds(opt, lower);
  nlopt_set_upper_bounds(opt, upper);
  nlopt_set_min_objective(opt, probe_objective, nullptr);
  nlopt_set_maxeval(opt, 20);
  nlopt_set_xtol_abs1(opt, 0);  // see configure(): MLSL crashes without it
  if (requires_local_optimizer(nlopt_algorithm_to_string(algorithm))) {
    nlopt_opt local = nlopt_create(NLOPT_LD_LBFGS, 2);
    nlopt_set_local_optimizer(opt, local);  // copies it
    nlopt_destroy(local);
  }
  double x[2] = {0.5, -0.5}, f = 0;
  const nlopt_result result = nlopt_optimize(opt, x, &f);
  nlopt_destroy(opt);
  return result;
}

// Whether this NLopt library can run `algorithm` at all. NLopt lists names it was built
// without and answers NLOPT_INVALID_ARGS for them on any problem: LD_LBFGS_NOCEDAL always
// (NLopt does not ship Nocedal's code), StoGO and AGS in a build without C++. Probed once per
// algorithm and process.
bool runs_in_this_build(int algorithm) {
  static std::mutex mutex;
  static std::map<int, bool> known;
  std::lock_guard<std::mutex> lock(mutex);
  const auto it = known.find(algorithm);
  if (it != known.end()) return it->second;
  return known[algorithm] = probe(static_cast<nlopt_algorithm>(algorithm)) != NLOPT_INVALID_ARGS;
}

// Cost reported at points where the residuals cannot be computed, times the worst cost seen.
constexpr double kPenaltyFactor = 10;
// A stop within this many times (n + 1) evaluations of an uncomputable point, at a point that
// is not stationary, is a stop at the edge of the region where residuals exist (lm's window
// is 10 iterations; an iteration of a gradient method costs about n + 1 evaluations' worth).
constexpr int kRecentEvaluations = 10;

// Why we forced NLopt to stop from inside the objective.
enum class ForcedStop { kNone, kCallback, kConverged, kBudget, kNonFinite };

// Objective state: evaluation counts, the best point so far, the trace.
struct Objective {
  Objective(const LeastSquaresProblem& problem, const SolverOptions& options, Summary& summary,
            detail::SolveMonitor& monitor)
      : problem(problem), options(options), summary(summary), monitor(monitor) {}

  const LeastSquaresProblem& problem;
  const SolverOptions& options;
  Summary& summary;
  detail::SolveMonitor& monitor;
  nlopt::opt* opt = nullptr;

  // kincal's tests, checked at every new best point that comes with a gradient: NLopt has no
  // gradient test, and its relative tests fire on short steps that need not end at a
  // stationary point. The residuals and Jacobian of the best point are kept for the verdict.
  StationarityScratch scratch{static_cast<int>(problem.num_residuals()), problem.num_parameters()};
  Stationarity at_best;
  std::string passed_test;  // the test that stopped the run (ForcedStop::kConverged)
  VectorXd best_r;
  MatrixXd best_J;
  bool best_has_jacobian = false;

  VectorXd x, r, gradient;
  MatrixXd J;
  // NLopt works on z = scale .* x (see the "scaling" option); the rest of us on x.
  VectorXd scale;
  // NLopt minimises objective_scale * cost (detail::objective_scale): the same minimum at a
  // scale that does not depend on the residuals' unit, which NLopt's algorithms would meet
  // with their own absolute constants.
  double objective_scale = 1;
  int evaluations = 0;       // calls from NLopt, which is what maxeval counts
  int failures = 0;          // calls where the residuals could not be computed
  int last_failure_at = 0;   // the evaluation count at the most recent of them
  bool last_failed = false;  // the most recent call was one of them
  std::string last_failure;
  ForcedStop forced = ForcedStop::kNone;

  VectorXd best_x;
  double best_cost = std::numeric_limits<double>::infinity();
  double worst_cost = 0;  // of the computable points: the scale of the failure penalty

  // NLopt's first call is at x0, which we already evaluated to record iteration 0.
  bool start_cached = false;
  VectorXd start_z;
  bool start_has_jacobian = false;

  // What NLopt is told an uncomputable point costs: much more than any point seen, relative to
  // them (an absolute floor would be no penalty at all for residuals in a large unit).
  double penalty() const { return worst_cost > 0 ? kPenaltyFactor * worst_cost : 1.0; }

  // Evaluates into r (and J when asked); false with last_failure set when not computable.
  bool evaluate(const VectorXd& at, bool with_jacobian) {
    ++summary.residual_evaluations;
    if (with_jacobian) ++summary.jacobian_evaluations;
    std::string why;
    last_failure_non_finite = false;
    if (!problem.evaluate(at, &r, with_jacobian ? &J : nullptr, &why, options.num_threads)) {
      last_failure = why;
      return false;
    }
    // A non-finite value is no cost and no gradient: NLopt would carry it into its state, and
    // our tests cannot judge a point with one (issue 35: a NaN Jacobian at the start passed).
    const MatrixXd* jacobian = with_jacobian ? &J : nullptr;
    if (!r.allFinite() || (jacobian && !jacobian->allFinite())) {
      last_failure = detail::non_finite_entry(r, jacobian, problem.parameter_names());
      last_failure_non_finite = true;
      return false;
    }
    if (with_jacobian) gradient.noalias() = J.transpose() * r;
    return true;
  }
  bool last_failure_non_finite = false;  // the last failure was a non-finite value

  double operator()(unsigned n, const double* x_in, double* grad) {
    if (evaluations >= options.max_iterations) {
      // Some algorithms (Luksan's L-BFGS and truncated Newton) test maxeval only once per
      // iteration and overshoot it; hold them to the budget without evaluating.
      forced = ForcedStop::kBudget;
      opt->force_stop();
      if (grad != nullptr) std::fill(grad, grad + n, 0.0);
      return objective_scale * penalty();
    }
    ++evaluations;
    x = Eigen::Map<const VectorXd>(x_in, n).cwiseQuotient(scale);
    const bool want_gradient = grad != nullptr;
    bool ok = true;
    if (start_cached && Eigen::Map<const VectorXd>(x_in, n) == start_z &&
        (!want_gradient || start_has_jacobian)) {
      x = best_x;
      start_cached = false;  // r, J and gradient still hold the start's values
    } else {
      start_cached = false;
      if (!x.allFinite()) {
        // The algorithm's own state broke down (seen with LD_MMA after thousands of
        // evaluations); every later point would be NaN too.
        last_failure = "NLopt proposed a non-finite point";
        forced = ForcedStop::kNonFinite;
        opt->force_stop();
        ok = false;
      } else {
        ok = evaluate(x, want_gradient);
      }
    }
    last_failed = !ok;
    if (!ok) {
      // Tell NLopt the point is much worse than any seen, and let it step back. The value is
      // finite on purpose: with +HUGE_VAL, NLopt 2.7's COBYLA loops forever, BOBYQA stops
      // early claiming xtol and NEWUOA returns NaN. The gradient is zero: no direction to
      // follow from there.
      ++failures;
      last_failure_at = evaluations;
      if (want_gradient) std::fill(grad, grad + n, 0.0);
      return objective_scale * penalty();
    }
    const double cost = 0.5 * r.squaredNorm();
    worst_cost = std::max(worst_cost, cost);
    if (want_gradient)
      Eigen::Map<VectorXd>(grad, n) = objective_scale * gradient.cwiseQuotient(scale);
    if (cost < best_cost) {
      const double step = (x - best_x).norm();
      best_cost = cost;
      best_x = x;
      best_r = r;
      best_has_jacobian = want_gradient;
      if (want_gradient) best_J = J;
      const double gradient_norm = want_gradient ? gradient.lpNorm<Eigen::Infinity>() : 0.0;
      if (!monitor.record({evaluations, cost, gradient_norm, step, 0, 0}, x)) {
        forced = ForcedStop::kCallback;
        opt->force_stop();
      } else if (want_gradient && converged_here()) {
        forced = ForcedStop::kConverged;
        opt->force_stop();
      }
    }
    return objective_scale * cost;
  }

  // Whether the best point, with r and J just evaluated there, passes one of kincal's tests
  // (or lies on a plateau, where nothing more can be learnt); names the test.
  bool converged_here() {
    measure_stationarity(best_x, r, J, options, scratch, at_best);
    if (at_best.on_plateau()) {
      passed_test = detail::kGradientTestMessage;
      return true;
    }
    if (at_best.gradient_test(options))
      passed_test = detail::kGradientTestMessage;
    else if (at_best.cost_test(options))
      passed_test = "relative cost change below tolerance";
    else if (at_best.step_test(options))
      passed_test = "relative step below tolerance";
    else
      return false;
    passed_test += " (kincal's test, at the best point)";
    return true;
  }

  static double call(unsigned n, const double* x, double* grad, void* self) {
    return (*static_cast<Objective*>(self))(n, x, grad);
  }
};

class NloptSolver final : public Solver {
 public:
  explicit NloptSolver(int algorithm)
      : algorithm_(static_cast<nlopt::algorithm>(algorithm)),
        algorithm_name_(nlopt_algorithm_to_string(static_cast<nlopt_algorithm>(algorithm))) {}

  std::string name() const override { return "nlopt:" + algorithm_name_; }
  std::unique_ptr<BackendSettings> default_settings() const override {
    return std::make_unique<NloptSettings>();
  }

  void check_options(const SolverOptions& options) const override {
    Solver::check_options(options);
    const NloptSettings settings = settings_for<NloptSettings>(name(), options);
    if (!settings.local_algorithm.empty()) {
      if (!takes_local_optimizer(algorithm_name_))
        throw InvalidSolverOptions(name() +
                                   ": local_algorithm applies only to the AUGLAG and MLSL "
                                   "algorithms, which run a subsidiary optimiser");
      const std::string& local = settings.local_algorithm;
      if (find_algorithm(local) < 0 || local[0] != 'L')
        throw InvalidSolverOptions(name() + ": local_algorithm='" + local +
                                   "' is not a local NLopt algorithm (LD_* or LN_*)");
    }
  }

  Summary solve(const LeastSquaresProblem& problem, VectorXd& x,
                const SolverOptions& options) const override {
    check_options(options);
    const int n = problem.num_parameters();
    check_sizes(problem, x, options);
    const std::string local_name = local_algorithm(options);
    const bool derivatives =
        uses_derivatives(algorithm_name_) || (!local_name.empty() && uses_derivatives(local_name));

    Summary summary;
    summary.solver = name();
    detail::SolveMonitor monitor(options, summary);
    // NLopt rejects a start outside the box: project it, as Ipopt does.
    if (options.lower_bounds) x = x.cwiseMax(*options.lower_bounds).cwiseMin(*options.upper_bounds);

    Objective objective(problem, options, summary, monitor);
    // With the Jacobian even without derivatives: a start where it has a non-finite entry
    // fails here, named, rather than after the whole run, at its verdict.
    if (!objective.evaluate(x, true)) {
      summary.initial_cost = summary.final_cost = std::numeric_limits<double>::infinity();
      monitor.finish(TerminationType::kFailed,
                     objective.last_failure_non_finite
                         ? detail::non_finite_start(objective.last_failure)
                         : "residuals not computable at the start: " + objective.last_failure);
      return summary;
    }
    objective.best_x = x;
    objective.best_r = objective.r;
    objective.best_has_jacobian = true;
    objective.best_J = objective.J;
    // In the scaled variables z (below), where every column has unit norm whatever this scale,
    // every column of the scaled problem gets a norm of at least 1024: Luksan's L-BFGS and
    // truncated Newton stop on their own at max|grad| <= 1e-6, an absolute test, which then
    // fires only after ours (measured on the test suite, solved starts of 116 with no headroom,
    // 2^5, 2^10, 2^20: L-BFGS 60, 68, 72, 77, truncated Newton 62, 68, 70, 66; 69 and 69 before,
    // unscaled). In the raw variables the largest column gets unit norm: SLSQP's first
    // quasi-Newton step, with the identity for the Hessian, is then no longer than the
    // Gauss-Newton model allows along any parameter.
    const bool scaled_variables = scaling(options) == "jacobian" && derivatives;
    objective.objective_scale =
        scaled_variables
            ? detail::objective_scale(objective.J, detail::ScaleBy::kSmallestColumn, 10)
            : detail::objective_scale(objective.J, detail::ScaleBy::kLargestColumn);
    objective.scale = VectorXd::Ones(n);
    // z_j = |J_j(x0)| x_j / sigma, with sigma^2 = 1 / objective_scale: what NLopt sees does
    // not depend on the residuals' unit either.
    if (scaled_variables)
      for (int j = 0; j < n; ++j) {
        const double norm = objective.J.col(j).norm() * std::sqrt(objective.objective_scale);
        if (norm > 0 && std::isfinite(norm)) objective.scale[j] = norm;
      }
    objective.best_cost = summary.initial_cost = summary.final_cost =
        0.5 * objective.r.squaredNorm();
    objective.start_cached = true;
    objective.start_has_jacobian = true;
    const double gradient_norm = derivatives ? objective.gradient.lpNorm<Eigen::Infinity>() : 0.0;
    if (!monitor.record({0, objective.best_cost, gradient_norm, 0, 0, 0}, x)) {
      monitor.finish(TerminationType::kUserStopped, "stopped by the callback");
      return summary;
    }
    if (derivatives && objective.converged_here()) {
      finish_judged(problem, objective, TerminationType::kConverged, objective.passed_test, monitor,
                    summary);
      return summary;
    }

    nlopt::result result = nlopt::FAILURE;
    std::string nlopt_error;
    try {
      nlopt::opt opt(algorithm_, static_cast<unsigned>(n));
      objective.opt = &opt;
      configure(opt, options, x, objective.scale, local_name);
      opt.set_min_objective(&Objective::call, &objective);
      // Stochastic algorithms draw from NLopt's (thread-local) generator: seed it so that a
      // run is reproducible.
      nlopt::srand(static_cast<unsigned long>(settings_for<NloptSettings>(name(), options).seed));
      objective.start_z = x.cwiseProduct(objective.scale);
      std::vector<double> xv(objective.start_z.data(), objective.start_z.data() + n);
      double f = 0;
      try {
        result = opt.optimize(xv, f);
      } catch (const std::exception& e) {
        // The C++ API throws for every negative result, after recording it.
        result = opt.last_optimize_result();
        nlopt_error = e.what();
      }
    } catch (const std::exception& e) {  // a setter refused (bad bounds, local optimiser, ...)
      result = nlopt::INVALID_ARGS;
      nlopt_error = e.what();
    }

    x = objective.best_x;
    summary.final_cost = objective.best_cost;
    summary.iterations = objective.evaluations;
    summary.backend_code = static_cast<int>(result);
    const auto [type, message] = termination(result, objective, nlopt_error);
    finish_judged(problem, objective, type, message, monitor, summary);
    return summary;
  }

 private:
  // Ends the solve; a convergence claim is judged at the best point, whose Jacobian a
  // derivative-free run has to evaluate for that (counted).
  static void finish_judged(const LeastSquaresProblem& problem, Objective& objective,
                            TerminationType type, std::string message,
                            detail::SolveMonitor& monitor, Summary& summary) {
    const int n = problem.num_parameters();
    if (type == TerminationType::kConverged) {
      bool known = objective.best_has_jacobian;
      if (!known) {
        ++summary.residual_evaluations;
        ++summary.jacobian_evaluations;
        known = problem.evaluate(objective.best_x, &objective.best_r, &objective.best_J, nullptr,
                                 objective.options.num_threads);
      }
      if (known) {
        const detail::Verdict verdict = detail::judge_convergence(
            measure_stationarity(objective.best_x, objective.best_r, objective.best_J,
                                 objective.options),
            objective.options, message, problem.parameter_names(),
            objective.failures > 0 &&
                objective.evaluations - objective.last_failure_at <= kRecentEvaluations * (n + 1));
        type = verdict.type;
        message = verdict.message;
      }
    }
    monitor.finish(type, std::move(message));
  }

  std::string local_algorithm(const SolverOptions& options) const {
    if (!takes_local_optimizer(algorithm_name_)) return "";
    const std::string given = settings_for<NloptSettings>(name(), options).local_algorithm;
    if (!given.empty()) return given;
    return requires_local_optimizer(algorithm_name_) ? kDefaultLocalAlgorithm : "";
  }

  std::string scaling(const SolverOptions& options) const {
    return settings_for<NloptSettings>(name(), options).scaling;
  }

  // Everything NLopt sees is in z = scale .* x.
  void configure(nlopt::opt& opt, const SolverOptions& options, const VectorXd& x0,
                 const VectorXd& scale, const std::string& local_name) const {
    const int n = static_cast<int>(x0.size());
    auto to_std = [&](const VectorXd& v) {
      const VectorXd z = v.cwiseProduct(scale);
      return std::vector<double>(z.data(), z.data() + z.size());
    };
    if (options.lower_bounds) {
      opt.set_lower_bounds(to_std(*options.lower_bounds));
      opt.set_upper_bounds(to_std(*options.upper_bounds));
    } else if (is_global(algorithm_name_)) {
      // Global algorithms search a finite box; without bounds from the caller, use x0 +- w.
      const double w = settings_for<NloptSettings>(name(), options).box_half_width;
      opt.set_lower_bounds(to_std((x0.array() - w).matrix()));
      opt.set_upper_bounds(to_std((x0.array() + w).matrix()));
    }
    // With derivatives, kincal's own tests decide convergence (checked at every new best
    // point, see Objective::converged_here): NLopt's relative tests fire on short steps that
    // need not end at a stationary point (SLSQP: measured on the MGH suite). Without, NLopt's.
    const bool ours = uses_derivatives(algorithm_name_);
    opt.set_ftol_rel(ours ? 0.0 : options.function_tolerance);
    opt.set_xtol_rel(ours ? 0.0 : options.parameter_tolerance);
    // 0 is NLopt's default (no absolute test), but setting it allocates the array: NLopt
    // 2.7.1 copies it, unallocated, into the default local optimiser of GN_MLSL/GD_MLSL and
    // their _LDS variants, and crashes (memcpy from null in nlopt_set_xtol_abs).
    opt.set_xtol_abs(0.0);
    opt.set_maxeval(options.max_iterations);
    const double initial_step = settings_for<NloptSettings>(name(), options).initial_step;
    if (initial_step > 0) opt.set_initial_step(to_std(VectorXd::Constant(n, initial_step)));
    if (!local_name.empty()) {
      nlopt::opt local(static_cast<nlopt::algorithm>(find_algorithm(local_name)),
                       static_cast<unsigned>(n));
      local.set_ftol_rel(options.function_tolerance);
      local.set_xtol_rel(options.parameter_tolerance);
      opt.set_local_optimizer(local);
    }
  }

  std::pair<TerminationType, std::string> termination(nlopt::result result,
                                                      const Objective& objective,
                                                      const std::string& nlopt_error) const {
    using T = TerminationType;
    const std::string failures =
        objective.failures == 0
            ? ""
            : "; the residuals failed at " + std::to_string(objective.failures) +
                  " of the points NLopt tried (last: " + objective.last_failure + ")";
    // Our own stops first: some algorithms (Luksan's) answer force_stop with FAILURE.
    switch (objective.forced) {
      case ForcedStop::kCallback:
        return {T::kUserStopped, "stopped by the callback"};
      case ForcedStop::kConverged:
        return {T::kConverged, objective.passed_test};
      case ForcedStop::kBudget:
        return {T::kMaxIterations, "reached max_iterations (" +
                                       std::to_string(objective.evaluations) +
                                       " objective evaluations; stopped by us, as NLopt "
                                       "was going past maxeval)" +
                                       failures};
      case ForcedStop::kNonFinite:
        return {T::kFailed, "NLopt proposed a non-finite point after " +
                                std::to_string(objective.evaluations) +
                                " evaluations; returning the best point seen"};
      case ForcedStop::kNone:
        break;
    }
    switch (result) {
      case nlopt::SUCCESS:
        return {T::kConverged, "NLopt reported success" + failures};
      case nlopt::STOPVAL_REACHED:
        return {T::kConverged, "cost reached stopval" + failures};
      case nlopt::FTOL_REACHED:
        return {T::kConverged, "relative cost change below tolerance (NLopt ftol_rel)" + failures};
      case nlopt::XTOL_REACHED:
        return {T::kConverged, "relative step below tolerance (NLopt xtol_rel)" + failures};
      case nlopt::MAXEVAL_REACHED:
        return {T::kMaxIterations, "reached max_iterations (" +
                                       std::to_string(objective.evaluations) +
                                       " objective evaluations, NLopt maxeval)" + failures};
      case nlopt::MAXTIME_REACHED:
        return {T::kMaxIterations, "reached NLopt maxtime" + failures};
      case nlopt::ROUNDOFF_LIMITED:
        // NLopt: "the optimization still typically returns a useful result". When points
        // outside the valid region were involved, the line search more likely choked on them.
        if (objective.last_failed)
          return {T::kDiverged,
                  "NLopt stopped, roundoff-limited, after leaving the valid region" + failures};
        return {T::kConverged,
                "NLopt stopped: roundoff errors limited progress (the point is "
                "usually still a good one)"};
      case nlopt::FORCED_STOP:
        return {T::kFailed, "NLopt forced stop: " + nlopt_error};
      case nlopt::FAILURE:
        if (objective.last_failed)
          return {T::kDiverged, "NLopt failed after leaving the valid region" + failures};
        // Luksan's methods (LD_LBFGS, LD_TNEWTON*, LD_VAR*) also say this when the line
        // search stalls, often at the minimum: a stop of the method's own, judged as a claim
        // (converged when the point passes one of our tests, a stall otherwise).
        return {T::kConverged, "NLopt failure (" + nlopt_error +
                                   "; from L-BFGS/TNEWTON usually a stalled line search)" +
                                   failures};
      case nlopt::INVALID_ARGS:
        return {T::kFailed, "NLopt rejected the arguments: " + nlopt_error};
      case nlopt::OUT_OF_MEMORY:
        return {T::kFailed, "NLopt ran out of memory"};
      default:
        return {T::kFailed, "unexpected NLopt result " + std::to_string(result)};
    }
  }

  nlopt::algorithm algorithm_;
  std::string algorithm_name_;
};

}  // namespace

const std::vector<SettingField<NloptSettings>>& NloptSettings::fields() {
  using S = NloptSettings;
  static const std::vector<SettingField<S>> fields = {
      {"initial_step", &S::initial_step},
      {"local_algorithm", &S::local_algorithm},
      {"box_half_width", &S::box_half_width},
      {"seed", &S::seed},
      {"scaling", &S::scaling, {"jacobian", "none"}}};
  return fields;
}

std::string NloptSettings::validity_error() const {
  if (!(initial_step >= 0)) return "initial_step must be > 0 (or 0: NLopt's own)";
  if (!(box_half_width > 0)) return "box_half_width must be > 0";
  if (seed < 0) return "seed must be >= 0";
  return {};
}

std::unique_ptr<Solver> make_nlopt_solver(const std::string& algorithm) {
  const int a = find_algorithm(algorithm);
  if (a < 0) {
    std::string list;
    for (const auto& name : all_algorithm_names()) list += (list.empty() ? "" : ", ") + name;
    throw InvalidSolverOptions("nlopt: unknown algorithm '" + algorithm + "' (valid: " + list +
                               ")");
  }
  if (!runs_in_this_build(a))
    throw InvalidSolverOptions(
        "nlopt: algorithm '" + algorithm +
        "' is not available in this NLopt library, which rejects it on any problem" +
        (algorithm == "LD_LBFGS_NOCEDAL"
             ? " (NLopt does not ship Nocedal's L-BFGS code; use LD_LBFGS)"
             : " (built without it)"));
  return std::make_unique<NloptSolver>(a);
}

std::vector<std::string> nlopt_featured_algorithms() {
  return {"LD_LBFGS", "LD_SLSQP",  "LD_TNEWTON_PRECOND_RESTART",
          "LD_MMA",   "LN_BOBYQA", "LN_NELDERMEAD",
          "LN_SBPLX", "LN_COBYLA"};
}

}  // namespace kincal
