#include "kincal/solvers/levenberg_marquardt.hpp"

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "kincal/framework/base/gram_matrix.hpp"
#include "kincal/framework/least_squares/robust_loss.hpp"
#include "kincal/solvers/schur_levenberg_marquardt.hpp"
#include "kincal/solvers/solver_common.hpp"

namespace kincal {
namespace {

enum class LinearSolver { kCholesky, kQr };

const char* const kSolverName = "lm";
// A convergence test that fires within this many iterations of a failed trial point is
// reported as stopped at the edge of the computable region (diverged), unless the gradient
// fell below this fraction of its starting value (a minimum that happens to lie near it).
constexpr int kFenceWindow = 10;
constexpr double kStationaryGradientRatio = 1e-4;
// The Marquardt scale of a parameter is the running maximum of its column norm (MINPACK),
// except when the column has fallen this far below it: the model then works in another regime
// (Brown almost-linear from 100 x0: the product's derivatives fall from 2e15 to 3e5), and a
// scale that large damps the parameter to a standstill even at the largest trust radius.
constexpr double kStaleScaleRatio = 1e6;
// Uphill steps are for the way to a minimum, not its end game, where rejected trials are
// rounding noise: only when the model promised at least this relative decrease (a noisy
// minimum) and the cost is this many times its rounding error (a zero-residual minimum: on
// the noise-free hexapod an uphill step of rounding size at cost 1e-21 ended in a stall).
constexpr double kUphillMinPredictedDecrease = 1e-6;
constexpr double kUphillMinCostOverRounding = 1e6;
// Geodesic acceleration bends long steps along a curved valley; in the end game, where the
// linear model promises less than this relative decrease, the correction is a 1e-3 or
// smaller fraction of the step (case 5: 4e-4 to 1e-5) and its probe, a whole residual
// evaluation, buys nothing: the plain step is taken instead.
constexpr double kAccelerationMinPredictedDecrease = 1e-6;

double max_norm(const VectorXd& v) { return v.size() == 0 ? 0.0 : v.lpNorm<Eigen::Infinity>(); }

// z <- Q^T z for a Householder QR, reflector by reflector (Q^T = H_{n-1} ... H_0). Eigen's
// HouseholderSequence allocates a workspace on every application.
void apply_q_transpose(const Eigen::HouseholderQR<MatrixXd>& qr, VectorXd& z) {
  const MatrixXd& reflectors = qr.matrixQR();
  const Eigen::Index rows = reflectors.rows();
  for (Eigen::Index k = 0; k < qr.hCoeffs().size(); ++k) {
    const auto essential = reflectors.col(k).tail(rows - k - 1);  // v_k = [1; essential]
    const double scale = qr.hCoeffs()[k] * (z[k] + essential.dot(z.tail(rows - k - 1)));
    z[k] -= scale;
    z.tail(rows - k - 1) -= scale * essential;
  }
}

class LevenbergMarquardtSolver final : public Solver {
 public:
  std::string name() const override { return kSolverName; }

  void check_options(const SolverOptions& options) const override {
    Solver::check_options(options);
    settings_for<LevenbergMarquardtSettings>(kSolverName, options);
  }
  std::unique_ptr<BackendSettings> default_settings() const override {
    return std::make_unique<LevenbergMarquardtSettings>();
  }
  bool takes_robust_loss() const override { return true; }

  Summary solve(const LeastSquaresProblem& problem, VectorXd& x,
                const SolverOptions& options) const override;

  // The Schur-complement solver takes lm's trust-region schedule and none of its other backend
  // options, nor bounds.
  bool solves_implicit(const SolverOptions& options) const override {
    LevenbergMarquardtSettings settings =
        settings_for<LevenbergMarquardtSettings>(kSolverName, options);
    const LevenbergMarquardtSettings defaults;
    settings.initial_trust_radius = defaults.initial_trust_radius;
    settings.max_radius_growth = defaults.max_radius_growth;
    return settings.in_force() == defaults.in_force() &&
           options.loss.kind == RobustLoss::Kind::kNone && !options.lower_bounds;
  }
  Summary solve_implicit(const ImplicitCalibrationProblem& problem, VectorXd& x,
                         const SolverOptions& options) const override {
    Solver::check_options(options);
    const auto settings = settings_for<LevenbergMarquardtSettings>(kSolverName, options);
    return solve_implicit_lm(problem, x, options,
                             {settings.initial_trust_radius, settings.max_radius_growth});
  }
};

// Everything one solve needs, sized once so that the iteration loop never allocates.
class LmWorkspace {
 public:
  LmWorkspace(int m, int n, LinearSolver linear_solver)
      : r(m),
        r_raw(m),
        r_trial(m),
        row_scale(m),
        residual_temp(m),
        J(m, n),
        J_trial(m, n),
        B(m, n),
        H(n, n),
        M(n, n),
        gradient(n),
        column_norm(n),
        column_scale(n),
        velocity(n),
        acceleration(n),
        y(n),
        dx(n),
        dx_velocity(n),
        x_trial(n),
        previous_step(n),
        active(n, 0),
        llt(n),
        scratch(m, n),
        best(n) {
    at_x.dead_parameters.reserve(static_cast<std::size_t>(n));
    if (linear_solver == LinearSolver::kQr) {
      qr = Eigen::HouseholderQR<MatrixXd>(m, n);
      augmented = MatrixXd(2 * n, n);
      augmented_qr = Eigen::HouseholderQR<MatrixXd>(2 * n, n);
      rhs = VectorXd(2 * n);
    }
  }

  VectorXd r;          // residuals at x, robust-corrected once the iterate is prepared
  VectorXd r_raw;      // residuals at x as evaluated
  VectorXd r_trial;    // residuals at a trial point
  VectorXd row_scale;  // per-residual Jacobian rescaling of the robust correction
  VectorXd residual_temp;
  MatrixXd J, J_trial;
  MatrixXd B;             // robust-corrected Jacobian in scaled variables, active columns zeroed
  MatrixXd H, M;          // B^T B, and B^T B + lambda I
  VectorXd gradient;      // J~^T r~ in x units
  VectorXd column_norm;   // |J~_j| at the iterate
  VectorXd column_scale;  // running max of the column norms of J~ (Marquardt diagonal)
  VectorXd velocity, acceleration, y;  // in scaled variables
  VectorXd dx, dx_velocity, x_trial;
  VectorXd previous_step;    // the last accepted step (uphill steps compare directions)
  std::vector<char> active;  // at a bound with the gradient pushing outwards
  Eigen::LLT<MatrixXd> llt;
  Eigen::HouseholderQR<MatrixXd> qr, augmented_qr;
  MatrixXd augmented;
  VectorXd rhs;
  StationarityScratch scratch;  // checking a convergence test at the iterate
  Stationarity at_x;
  detail::BestPoint best;  // over every point evaluated: iterates, trials, probes
};

Summary LevenbergMarquardtSolver::solve(const LeastSquaresProblem& problem, VectorXd& x,
                                        const SolverOptions& options) const {
  Solver::check_options(options);
  const auto settings = settings_for<LevenbergMarquardtSettings>(kSolverName, options);
  const LinearSolver linear_solver =
      settings.linear_solver == "qr" ? LinearSolver::kQr : LinearSolver::kCholesky;
  const int m = problem.num_residuals(), n = problem.num_parameters();
  check_sizes(problem, x, options);
  const bool bounded = options.lower_bounds.has_value();
  auto project = [&](VectorXd& v) {
    if (bounded) v = v.cwiseMax(*options.lower_bounds).cwiseMin(*options.upper_bounds);
  };

  Summary summary;
  summary.solver = name();
  detail::SolveMonitor monitor(options, summary);
  // The trace is the only growing container: reserve it so the loop does not allocate.
  summary.trace.reserve(static_cast<std::size_t>(std::min(options.max_iterations, 10000)) + 1);

  LmWorkspace ws(m, n, linear_solver);
  const RobustLoss& loss = options.loss;
  project(x);  // the box applies to the start too
  const VectorXd x0 = x;
  const double runaway = settings.runaway_factor * (1.0 + max_norm(x0));

  // Forward kinematics starts from the poses of this solve's last evaluation: the trust region
  // keeps trial points near the iterate, so one to three Newton steps instead of about four
  // from home (lm on case 5: 2.6 -> 1.9 ms). Not in the other backends (gn, Ceres, NLopt), whose
  // end games measured worse with it (docs/architecture.md, "Warm starts").
  const std::unique_ptr<WarmStart> warm = problem.make_warm_start();
  std::string why;
  ++summary.residual_evaluations;
  ++summary.jacobian_evaluations;
  if (!problem.evaluate(x, &ws.r, &ws.J, &why, options.num_threads, warm.get())) {
    summary.initial_cost = summary.final_cost = std::numeric_limits<double>::infinity();
    monitor.finish(TerminationType::kFailed, "residuals not computable at the start: " + why);
    return summary;
  }
  double cost = loss.cost(ws.r);
  const std::string non_finite = detail::non_finite_start(ws.r, &ws.J, problem.parameter_names());
  if (!non_finite.empty() || !std::isfinite(cost)) {
    summary.initial_cost = summary.final_cost = std::numeric_limits<double>::infinity();
    monitor.finish(TerminationType::kFailed,
                   non_finite.empty() ? "the cost at the start is not finite" : non_finite);
    return summary;
  }
  summary.initial_cost = summary.final_cost = cost;
  ws.best.offer(x, cost);
  ws.column_scale.setZero();

  // Prepares the linear model at the current (accepted) iterate: robust correction,
  // gradient, Marquardt scaling, active bounds, and what the trials factorise.
  // Returns the projected-gradient max-norm (Ceres' quantity, for the trace) and sets
  // relative_gradient, the gradient test's measure (stationarity.hpp) before rounding.
  double relative_gradient = 0;
  auto prepare_iterate = [&]() {
    ws.r_raw = ws.r;
    loss.correct(ws.r, ws.J, ws.row_scale);
    ws.gradient.noalias() = ws.J.transpose() * ws.r;
    for (int j = 0; j < n; ++j) {
      const double norm = ws.column_norm[j] = ws.J.col(j).norm();
      ws.column_scale[j] =
          ws.column_scale[j] > kStaleScaleRatio * norm ? norm : std::max(ws.column_scale[j], norm);
    }
    // A column that never moved the residuals gets a tiny positive scale: its damping row
    // then pins that parameter (y_j = 0) instead of dividing by zero. Relative to the largest
    // column, so that a common scale of the residuals changes nothing (1 when all vanished).
    const double largest = max_norm(ws.column_scale);
    const double floor = largest > 0 ? 1e-12 * largest : 1.0;
    const double residual_norm = ws.r.norm();
    double gradient_norm = 0;
    relative_gradient = 0;
    for (int j = 0; j < n; ++j) {
      ws.column_scale[j] = std::max(ws.column_scale[j], floor);
      double projected = ws.gradient[j];
      double lo = -HUGE_VAL, hi = HUGE_VAL;
      ws.active[j] = 0;
      if (bounded) {
        lo = (*options.lower_bounds)[j];
        hi = (*options.upper_bounds)[j];
        projected = x[j] - std::min(hi, std::max(lo, x[j] - ws.gradient[j]));
        ws.active[j] = (x[j] <= lo && ws.gradient[j] > 0) || (x[j] >= hi && ws.gradient[j] < 0);
      }
      gradient_norm = std::max(gradient_norm, std::abs(projected));
      if (!dead_column(ws.column_norm[j], x[j], residual_norm))
        relative_gradient =
            std::max(relative_gradient, relative_gradient_entry(ws.gradient[j], ws.column_norm[j],
                                                                residual_norm, x[j], lo, hi));
    }
    // Scaled variables y = D^(1/2) dx: B's columns have norm <= 1, which keeps the damped
    // system well conditioned even when cond(J) is ~1e5.
    ws.B.noalias() = ws.J * ws.column_scale.cwiseInverse().asDiagonal();
    for (int j = 0; j < n; ++j)
      if (ws.active[j]) ws.B.col(j).setZero();
    if (linear_solver == LinearSolver::kCholesky) {
      gram_lower(ws.B, ws.H);
    } else {
      ws.qr.compute(ws.B);
    }
    return gradient_norm;
  };

  // Factorises the damped system for lambda; false when that failed.
  auto factorize = [&](double lambda) {
    if (linear_solver == LinearSolver::kCholesky) {
      ws.M = ws.H;
      ws.M.diagonal().array() += lambda;
      ws.llt.compute(ws.M);
      return ws.llt.info() == Eigen::Success;
    }
    // MINPACK's way: B = QR once per iterate, then only a 2n x n QR of [R; sqrt(lambda) I].
    const int k = std::min(m, n);
    ws.augmented.setZero();
    ws.augmented.topRows(k) = ws.qr.matrixQR().topRows(k).triangularView<Eigen::Upper>();
    ws.augmented.bottomRows(n).diagonal().setConstant(std::sqrt(lambda));
    ws.augmented_qr.compute(ws.augmented);
    return true;
  };
  // out = argmin |B out + z|^2 + lambda |out|^2 with the current factorisation; z is
  // overwritten. False when the result is not finite.
  auto damped_solve = [&](VectorXd& z, VectorXd& out) {
    if (linear_solver == LinearSolver::kCholesky) {
      out.noalias() = -ws.B.transpose() * z;
      ws.llt.solveInPlace(out);
    } else {
      const int k = std::min(m, n);
      apply_q_transpose(ws.qr, z);
      ws.rhs.setZero();
      ws.rhs.head(k) = -z.head(k);
      apply_q_transpose(ws.augmented_qr, ws.rhs);
      out = ws.rhs.head(n);
      ws.augmented_qr.matrixQR().topRows(n).triangularView<Eigen::Upper>().solveInPlace(out);
    }
    return out.allFinite();
  };

  double gradient_norm = prepare_iterate();
  ws.previous_step.setZero();
  const double initial_gradient_norm = gradient_norm;
  double radius = settings.initial_trust_radius;
  double decrease_factor = 2;
  if (!monitor.record({0, cost, gradient_norm, 0, 1.0 / radius, 0}, x)) {
    monitor.finish(TerminationType::kUserStopped, "stopped by the callback");
    return summary;
  }
  // Trial points where the residuals could not be computed (forward kinematics failed).
  int failed_trials = 0, last_failed_iteration = -1;
  std::string first_failure;
  auto done = [&](TerminationType type, std::string message) {
    // The lowest cost evaluated may be a geodesic probe, a trial the gain ratio rejected or
    // an iterate before an uphill step rather than the current iterate: return it (the contract),
    // and check a convergence claim again there, which needs its Jacobian. Not when it is lower by
    // less than the cost's rounding error: near a noisy minimum (the hexapod's) that is noise, and
    // the iterate is the point the tests were passed at.
    if (ws.best.cost() < cost - cost_rounding(x, ws.r, ws.J)) {
      x = ws.best.x();
      cost = ws.best.cost();
      if (type == TerminationType::kConverged) {
        ++summary.residual_evaluations;
        ++summary.jacobian_evaluations;
        if (problem.evaluate(x, &ws.r, &ws.J, &why, options.num_threads, warm.get())) {
          loss.correct(ws.r, ws.J, ws.row_scale);
          measure_stationarity(x, ws.r, ws.J, options, ws.scratch, ws.at_x);
          const detail::Verdict verdict =
              detail::judge_convergence(ws.at_x, options, message, problem.parameter_names());
          type = verdict.type;
          message = verdict.message;
        }
      }
    }
    summary.final_cost = cost;
    if (failed_trials > 0) {
      // "Converged" right after trials failed, with a gradient that has not vanished,
      // means the iterates were stopped by the edge of the region where residuals can be
      // computed, not at a minimum: ceres and ipopt call that diverged too.
      if (type == TerminationType::kConverged &&
          summary.iterations - last_failed_iteration <= kFenceWindow &&
          gradient_norm > kStationaryGradientRatio * initial_gradient_norm) {
        type = TerminationType::kDiverged;
        message =
            "stopped at the edge of the region where residuals can be computed (" + message + ")";
      }
      message += " (residuals failed at " + std::to_string(failed_trials) +
                 " trial points; first: " + first_failure + ")";
    }
    monitor.finish(type, std::move(message));
    return summary;
  };
  // A convergence test fired at the current iterate (r, J prepared there): measures it and
  // says whether to stop, i.e. whether the iterate passes the test (docs/solvers.md, the
  // honesty contract) or is on a plateau, where nothing more can be done. Does not allocate.
  auto test_holds = [&](bool gradient_claim) {
    measure_stationarity(x, ws.r, ws.J, options, ws.scratch, ws.at_x);
    return ws.at_x.on_plateau() || ws.at_x.claim_holds(options, gradient_claim);
  };
  // Ends the solve on the test that fired, as judged at the iterate by test_holds.
  auto conclude = [&](const std::string& message) {
    const bool near_uncomputable =
        failed_trials > 0 && summary.iterations - last_failed_iteration <= kFenceWindow;
    const detail::Verdict verdict = detail::judge_convergence(
        ws.at_x, options, message, problem.parameter_names(), near_uncomputable);
    return done(verdict.type, verdict.message);
  };
  // Ceres' (and Nielsen's) response to a bad trial: shrink ever faster.
  auto reject = [&] {
    radius /= decrease_factor;
    decrease_factor *= 2;
  };

  int consecutive_invalid = 0;
  for (int iteration = 1;; ++iteration) {
    // These two end the solve either way: no step can be found (the verdict may be a stall).
    if (relative_gradient <= options.gradient_tolerance) {
      test_holds(true);
      return conclude(detail::kGradientTestMessage);
    }
    if (radius < settings.min_trust_radius) {
      test_holds(false);
      return conclude("trust region radius below min_trust_radius");
    }
    if (iteration > options.max_iterations)
      return done(TerminationType::kMaxIterations, "reached max_iterations");
    summary.iterations = iteration;

    const double lambda = 1.0 / radius;
    ws.residual_temp = ws.r;
    if (!factorize(lambda) || !damped_solve(ws.residual_temp, ws.velocity)) {
      if (++consecutive_invalid > settings.max_invalid_steps)
        return done(TerminationType::kDiverged, "damped normal equations could not be solved");
      reject();
      continue;
    }
    ws.dx_velocity.noalias() = ws.column_scale.cwiseInverse().asDiagonal() * ws.velocity;
    ws.y = ws.velocity;
    ws.residual_temp.noalias() = ws.J * ws.dx_velocity;
    const double velocity_decrease =
        -(ws.gradient.dot(ws.dx_velocity) + 0.5 * ws.residual_temp.squaredNorm());

    // Ceres' relative cost test applied to the linear model: when the damping is not what
    // holds the step back (lambda <= 1, against a scaled Hessian whose diagonal is <= 1) and
    // even the model promises a relative decrease below function_tolerance, no step can
    // pass that test. Near the minimum of a noisy problem the actual cost change is then
    // rounding noise (the residuals are differences of ~600 mm lengths, good to ~1e-13 mm)
    // and used to be chased with rejected trials, each a full evaluation. Instead: take
    // this last step if it does not raise the cost, and stop.
    if (lambda <= 1.0 && consecutive_invalid == 0 && !bounded) {
      // The iterate must pass the test as the contract recomputes it; when it does not (the
      // damping still shapes the step), the iteration goes on.
      if (velocity_decrease <= options.function_tolerance * cost && test_holds(false)) {
        ws.x_trial = x + ws.dx_velocity;
        // With its Jacobian: when the step is taken, the verdict is judged where it ends (the
        // contract's point). Judged before the step, a claim could outlive it: on Biggs EXP6
        // from 100 x0 with other trust-region settings, the step off a plateau left a point
        // that passes none of the tests.
        ++summary.residual_evaluations;
        ++summary.jacobian_evaluations;
        if (problem.evaluate(ws.x_trial, &ws.r_trial, &ws.J_trial, nullptr, options.num_threads,
                             warm.get()) &&
            ws.J_trial.allFinite()) {
          const double cost_trial = loss.cost(ws.r_trial);
          if (cost_trial < cost) {
            x.swap(ws.x_trial);
            ws.r.swap(ws.r_trial);
            ws.J.swap(ws.J_trial);
            cost = cost_trial;
            ws.best.offer(x, cost);
            loss.correct(ws.r, ws.J, ws.row_scale);
            test_holds(false);  // measures the new iterate for conclude()
            if (!monitor.record(
                    {iteration, cost, gradient_norm, ws.dx_velocity.norm(), 1.0 / radius, 0}, x))
              return done(TerminationType::kUserStopped, "stopped by the callback");
          }
        }
        return conclude("predicted relative cost decrease below tolerance");
      }
    }

    // Geodesic acceleration (Transtrum & Sethna 2012): a second-order correction that lets
    // the step follow the curved, flat valleys of this problem instead of crawling along
    // them. Needs one residual evaluation at x + h v.
    bool accelerated = false;
    if (settings.geodesic_acceleration &&
        velocity_decrease > kAccelerationMinPredictedDecrease * cost) {
      const double h = settings.geodesic_step;
      ws.x_trial = x + h * ws.dx_velocity;
      project(ws.x_trial);
      ++summary.residual_evaluations;
      if (problem.evaluate(ws.x_trial, &ws.r_trial, nullptr, nullptr, options.num_threads,
                           warm.get()) &&
          ws.r_trial.allFinite()) {
        ws.best.offer(ws.x_trial, loss.cost(ws.r_trial));
        // Directional second derivative of the corrected residuals along v.
        ws.residual_temp.noalias() = ws.J * ws.dx_velocity;
        ws.residual_temp =
            (2.0 / h) * ((ws.row_scale.array() * (ws.r_trial - ws.r_raw).array() / h).matrix() -
                         ws.residual_temp);
        // Where the correction is large compared with the step (the valley bends sharply, or
        // near convergence the difference is round-off) the plain step is used instead.
        if (damped_solve(ws.residual_temp, ws.acceleration) &&
            2.0 * ws.acceleration.norm() <= settings.max_acceleration * ws.velocity.norm()) {
          ws.y += 0.5 * ws.acceleration;
          accelerated = true;
        }
      }
    }

    ws.dx.noalias() = ws.column_scale.cwiseInverse().asDiagonal() * ws.y;
    ws.x_trial = x + ws.dx;
    project(ws.x_trial);
    ws.dx = ws.x_trial - x;
    // Not after unusable trials: a step shrunk to nothing because the residuals cannot be
    // computed ahead says nothing about convergence.
    if (consecutive_invalid == 0 && detail::small_step(ws.dx, x, options.parameter_tolerance) &&
        test_holds(false))
      return conclude("relative step below tolerance");
    if ((ws.x_trial - x0).lpNorm<Eigen::Infinity>() > runaway)
      return done(TerminationType::kDiverged, "parameters ran away (moved more than " +
                                                  std::to_string(runaway) + " from the start)");

    ++summary.residual_evaluations;
    ++summary.jacobian_evaluations;
    const bool evaluated = problem.evaluate(ws.x_trial, &ws.r_trial, &ws.J_trial, &why,
                                            options.num_threads, warm.get());
    const double cost_trial =
        evaluated ? loss.cost(ws.r_trial) : std::numeric_limits<double>::infinity();
    if (!std::isfinite(cost_trial) || !ws.J_trial.allFinite()) {
      // Forward kinematics failed (or produced garbage) at the trial point: a rejected step.
      if (failed_trials++ == 0) first_failure = evaluated ? "not finite" : why;
      last_failed_iteration = iteration;
      if (++consecutive_invalid > settings.max_invalid_steps)
        return done(TerminationType::kDiverged,
                    std::to_string(consecutive_invalid) +
                        " consecutive trial points where residuals could not be computed");
      reject();
      continue;
    }
    consecutive_invalid = 0;
    ws.best.offer(ws.x_trial, cost_trial);

    // Gain ratio rho = actual / predicted reduction of the (robust-corrected) linear model.
    // With acceleration the prediction is that of the velocity alone: the correction is
    // there to make the real step achieve what the linear model promised for v.
    if (accelerated) {
      ws.dx_velocity += x;
      project(ws.dx_velocity);
      ws.dx_velocity -= x;
    }
    const VectorXd& model_step = accelerated ? ws.dx_velocity : ws.dx;
    ws.residual_temp.noalias() = ws.J * model_step;
    const double predicted = -(ws.gradient.dot(model_step) + 0.5 * ws.residual_temp.squaredNorm());
    const double actual = cost - cost_trial;
    const double rho = predicted > 0 ? actual / predicted : -1.0;
    const bool cost_flat = detail::small_cost_change(cost, cost_trial, options.function_tolerance);
    const bool downhill = actual > 0 && rho > settings.min_relative_decrease;
    // Uphill steps (Transtrum & Sethna 2012): a trial that raises the cost is still taken
    // when it keeps the direction of the previous step, i.e. the iterates are following a
    // curved valley rather than bouncing across it: cos(angle) = beta, accepted when
    // (1 - beta)^2 cost_trial <= best cost. Capped at max_uphill_ratio times the best cost,
    // and kept out of the end game; the best point evaluated is still what is returned.
    bool uphill = false;
    if (!downhill && settings.uphill_steps && predicted > kUphillMinPredictedDecrease * cost &&
        cost > kUphillMinCostOverRounding * cost_rounding(x, ws.r, ws.J)) {
      const double norms = ws.dx.norm() * ws.previous_step.norm();
      const double beta = norms > 0 ? ws.dx.dot(ws.previous_step) / norms : -1.0;
      uphill = (1.0 - beta) * (1.0 - beta) * cost_trial <= ws.best.cost() &&
               cost_trial <= settings.max_uphill_ratio * ws.best.cost();
    }
    if (options.verbosity > 1)
      std::fprintf(stderr, "lm   trial %3d  cost %.9e  rho %+.3e  |dx| %.3e  lambda %.3e%s\n",
                   iteration, cost_trial, rho, ws.dx.norm(), lambda, uphill ? "  uphill" : "");
    if (downhill || uphill) {
      ws.previous_step = ws.dx;
      x.swap(ws.x_trial);
      ws.r.swap(ws.r_trial);
      ws.J.swap(ws.J_trial);
      cost = cost_trial;
      // An uphill step says nothing good about the model: the radius stays.
      if (downhill)
        radius = std::min(settings.max_trust_radius,
                          radius / std::max(1.0 / settings.max_radius_growth,
                                            1.0 - std::pow(2.0 * rho - 1.0, 3)));
      decrease_factor = 2;
      gradient_norm = prepare_iterate();
      if (!monitor.record({iteration, cost, gradient_norm, ws.dx.norm(), 1.0 / radius, 0}, x))
        return done(TerminationType::kUserStopped, "stopped by the callback");
    } else {
      reject();
    }
    if (cost_flat && test_holds(false)) return conclude("relative cost change below tolerance");
  }
}

}  // namespace

const std::vector<SettingField<LevenbergMarquardtSettings>>& LevenbergMarquardtSettings::fields() {
  using S = LevenbergMarquardtSettings;
  static const std::vector<SettingField<S>> fields = {
      {"linear_solver", &S::linear_solver, {"cholesky", "qr"}},
      {"initial_trust_radius", &S::initial_trust_radius},
      {"max_trust_radius", &S::max_trust_radius},
      {"min_trust_radius", &S::min_trust_radius},
      {"min_relative_decrease", &S::min_relative_decrease},
      {"max_radius_growth", &S::max_radius_growth},
      {"max_invalid_steps", &S::max_invalid_steps},
      {"runaway_factor", &S::runaway_factor, {}, "none"},
      {"geodesic_acceleration", &S::geodesic_acceleration},
      {"geodesic_step", &S::geodesic_step},
      {"max_acceleration", &S::max_acceleration},
      {"uphill_steps", &S::uphill_steps},
      {"max_uphill_ratio", &S::max_uphill_ratio}};
  return fields;
}

std::string LevenbergMarquardtSettings::validity_error() const {
  // Written as !(a > b) so that NaN is rejected too.
  if (!(min_trust_radius > 0)) return "min_trust_radius must be > 0";
  if (!(max_trust_radius >= min_trust_radius && std::isfinite(max_trust_radius)))
    return "max_trust_radius must be finite and >= min_trust_radius";
  if (!(initial_trust_radius >= min_trust_radius && initial_trust_radius <= max_trust_radius))
    return "initial_trust_radius must lie in [min_trust_radius, max_trust_radius]";
  if (!(min_relative_decrease >= 0 && min_relative_decrease < 1))
    return "min_relative_decrease must be in [0, 1)";
  if (!(max_radius_growth > 1)) return "max_radius_growth must be > 1";
  if (!(max_invalid_steps >= 1)) return "max_invalid_steps must be >= 1";
  if (!(runaway_factor > 0)) return "runaway_factor must be > 0 (or none)";
  if (!(geodesic_step > 0 && geodesic_step <= 1)) return "geodesic_step must be in (0, 1]";
  if (!(max_acceleration > 0)) return "max_acceleration must be > 0";
  if (!(max_uphill_ratio >= 1 && std::isfinite(max_uphill_ratio)))
    return "max_uphill_ratio must be finite and >= 1";
  return {};
}

std::unique_ptr<Solver> make_levenberg_marquardt_solver() {
  return std::make_unique<LevenbergMarquardtSolver>();
}

}  // namespace kincal
