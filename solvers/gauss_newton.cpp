#include "kincal/solvers/gauss_newton.hpp"

#include <Eigen/QR>
#include <cmath>
#include <limits>

#include "kincal/solvers/solver_common.hpp"

namespace kincal {
namespace {

class GaussNewtonSolver final : public Solver {
 public:
  std::string name() const override { return "gn"; }

  void check_options(const SolverOptions& options) const override {
    Solver::check_options(options);
    settings_for<GaussNewtonSettings>(name(), options);
    // Undamped full steps have no way to stay in a box; ignoring one would return a point
    // outside the bounds the caller asked for.
    if (options.lower_bounds || options.upper_bounds)
      throw InvalidSolverOptions(
          "gn: bounds are not supported (the paper's undamped Gauss-Newton cannot honour a "
          "box); use lm, ceres, nlopt:<ALGORITHM> or ipopt");
  }

  std::unique_ptr<BackendSettings> default_settings() const override {
    return std::make_unique<GaussNewtonSettings>();
  }

  Summary solve(const LeastSquaresProblem& problem, VectorXd& x,
                const SolverOptions& options) const override {
    check_options(options);
    check_sizes(problem, x, options);
    // Parameters "run away" when they move further than this from the start.
    const double runaway_factor = settings_for<GaussNewtonSettings>(name(), options).runaway_factor;
    Summary summary;
    summary.solver = name();
    detail::SolveMonitor monitor(options, summary);

    const int m = problem.num_residuals(), n = problem.num_parameters();
    VectorXd r(m), r_new(m);
    MatrixXd J(m, n), J_new(m, n);
    std::string why;
    ++summary.residual_evaluations;
    ++summary.jacobian_evaluations;
    if (!problem.evaluate(x, &r, &J, &why, options.num_threads)) {
      summary.initial_cost = summary.final_cost = std::numeric_limits<double>::infinity();
      monitor.finish(TerminationType::kFailed, "residuals not computable at the start: " + why);
      return summary;
    }
    const std::string non_finite = detail::non_finite_start(r, &J, problem.parameter_names());
    if (!non_finite.empty() || !std::isfinite(0.5 * r.squaredNorm())) {
      summary.initial_cost = summary.final_cost = std::numeric_limits<double>::infinity();
      monitor.finish(TerminationType::kFailed,
                     non_finite.empty() ? "the cost at the start is not finite" : non_finite);
      return summary;
    }
    const VectorXd x0 = x;
    const double runaway = runaway_factor * (1.0 + x0.lpNorm<Eigen::Infinity>());
    double cost = 0.5 * r.squaredNorm();
    summary.initial_cost = summary.final_cost = cost;
    // The lowest-cost iterate, with its residuals and Jacobian: undamped steps may go uphill,
    // and a convergence test firing later is checked again where we return.
    VectorXd best_x = x, best_r = r;
    MatrixXd best_J = J;
    double best_cost = cost;

    Eigen::ColPivHouseholderQR<MatrixXd> qr(m, n);
    VectorXd gradient(n), dx(n), x_new(n);
    gradient.noalias() = J.transpose() * r;
    if (!monitor.record({0, cost, gradient.lpNorm<Eigen::Infinity>(), 0, 0, 0}, x)) {
      monitor.finish(TerminationType::kUserStopped, "stopped by the callback");
      return summary;
    }

    auto done = [&](TerminationType type, std::string message) {
      x = best_x;
      summary.final_cost = best_cost;
      if (type == TerminationType::kConverged) {
        // The test fired at the current iterate, which may cost more than the point returned.
        const detail::Verdict verdict =
            detail::judge_convergence(measure_stationarity(x, best_r, best_J, options), options,
                                      message, problem.parameter_names());
        type = verdict.type;
        message = verdict.message;
      }
      monitor.finish(type, std::move(message));
      return summary;
    };

    for (int iteration = 1;; ++iteration) {
      // Relative to |J_j| |r| (stationarity.hpp), so that a common scale of the residuals does
      // not decide when to stop.
      if (relative_gradient(x, r, J, options) <= options.gradient_tolerance)
        return done(TerminationType::kConverged, detail::kGradientTestMessage);
      if (iteration > options.max_iterations)
        return done(TerminationType::kMaxIterations, "reached max_iterations");
      summary.iterations = iteration;  // attempted, as lm counts its trials
      // Gauss-Newton step: least-squares solution of J dx = -r.
      qr.compute(J);
      dx.noalias() = -qr.solve(r);
      if (!dx.allFinite()) return done(TerminationType::kDiverged, "step is not finite");
      x_new = x + dx;
      if ((x_new - x0).lpNorm<Eigen::Infinity>() > runaway)
        return done(TerminationType::kDiverged, "parameters ran away (moved more than " +
                                                    std::to_string(runaway) + " from the start)");
      ++summary.residual_evaluations;
      ++summary.jacobian_evaluations;
      if (!problem.evaluate(x_new, &r_new, &J_new, &why, options.num_threads))
        return done(TerminationType::kDiverged,
                    "iterate " + std::to_string(iteration) + " left the valid region: " + why);
      const double cost_new = 0.5 * r_new.squaredNorm();
      // Undamped: the step is taken whether or not the cost went down (the paper's method).
      const bool step_small = detail::small_step(dx, x, options.parameter_tolerance);
      const bool cost_flat = detail::small_cost_change(cost, cost_new, options.function_tolerance);
      x.swap(x_new);
      r.swap(r_new);
      J.swap(J_new);
      cost = cost_new;
      if (cost < best_cost) {
        best_cost = cost;
        best_x = x;
        best_r = r;
        best_J = J;
      }
      gradient.noalias() = J.transpose() * r;
      if (!monitor.record({iteration, cost, gradient.lpNorm<Eigen::Infinity>(), dx.norm(), 0, 0},
                          x))
        return done(TerminationType::kUserStopped, "stopped by the callback");
      if (step_small) return done(TerminationType::kConverged, "relative step below tolerance");
      if (cost_flat)
        return done(TerminationType::kConverged, "relative cost change below tolerance");
    }
  }
};

}  // namespace

const std::vector<SettingField<GaussNewtonSettings>>& GaussNewtonSettings::fields() {
  static const std::vector<SettingField<GaussNewtonSettings>> fields = {
      {"runaway_factor", &GaussNewtonSettings::runaway_factor}};
  return fields;
}

std::string GaussNewtonSettings::validity_error() const {
  return runaway_factor > 0 ? std::string() : "runaway_factor must be > 0";
}

std::unique_ptr<Solver> make_gauss_newton_solver() { return std::make_unique<GaussNewtonSolver>(); }

}  // namespace kincal
