#include "kincal/solvers/ceres_solver.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "kincal/framework/least_squares/robust_loss.hpp"
#include "kincal/solvers/solver_common.hpp"

namespace kincal {
namespace {

// Below this many residual blocks per thread, Ceres runs on one (see solve()).
constexpr int kMinBlocksPerCeresThread = 256;

// Ceres logs through glog, whose flags belong to the host program: this backend never
// changes them (a host that set up its logging keeps it). It stays quiet by other means:
// Ceres' own progress logging is off (logging_type SILENT), and a block whose residuals or
// Jacobian are not finite is reported as a failed evaluation (BlockCost::Evaluate) instead
// of being handed to Ceres, whose check of such values warns through glog.

// The first reason a block could not be evaluated, shared by all cost functions of a solve
// (Ceres may call them from several threads).
struct FailureLog {
  std::mutex mutex;
  std::string first;
  int count = 0;
  void add(const std::string& why) {
    std::lock_guard<std::mutex> lock(mutex);
    if (count++ == 0) first = why;
  }
  int total() {
    std::lock_guard<std::mutex> lock(mutex);
    return count;
  }
};

// Every point Ceres evaluates, assembled from its residual blocks (Ceres evaluates all blocks
// at one point before moving to the next, possibly on several threads): the lowest cost seen,
// which is what we return (Ceres keeps its last accepted iterate, and rejects trial points of
// lower cost when the gain ratio is small), and the residuals and Jacobian of the last point
// whose Jacobian was evaluated, which at the end is Ceres' final iterate.
class EvaluationLog {
 public:
  EvaluationLog(int blocks, int k, int n)
      : k_(k),
        cost_point_(n),
        cost_done_(static_cast<std::size_t>(blocks), 0),
        jacobian_point_(n),
        jacobian_done_(static_cast<std::size_t>(blocks), 0),
        r_(blocks * k),
        J_(blocks * k, n),
        best_(n) {}

  void add(int block, const VectorXd& x, const Eigen::Ref<const VectorXd>& r, const MatrixXd* J) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (x != cost_point_ || !cost_started_) {
      finish_point();
      cost_point_ = x;
      cost_started_ = true;
      std::fill(cost_done_.begin(), cost_done_.end(), 0);
      cost_blocks_ = 0;
      cost_sum_ = 0;
    }
    if (!cost_done_[static_cast<std::size_t>(block)]) {
      cost_done_[static_cast<std::size_t>(block)] = 1;
      ++cost_blocks_;
      cost_sum_ += r.squaredNorm();
    }
    if (!J) return;
    if (x != jacobian_point_ || !jacobian_started_) {
      jacobian_point_ = x;
      jacobian_started_ = true;
      std::fill(jacobian_done_.begin(), jacobian_done_.end(), 0);
      jacobian_blocks_ = 0;
    }
    if (!jacobian_done_[static_cast<std::size_t>(block)]) {
      jacobian_done_[static_cast<std::size_t>(block)] = 1;
      ++jacobian_blocks_;
      r_.segment(block * k_, k_) = r;
      J_.middleRows(block * k_, k_) = *J;
    }
  }
  /// Offers the point being assembled (call once Ceres has returned).
  void finish() {
    std::lock_guard<std::mutex> lock(mutex_);
    finish_point();
  }
  const detail::BestPoint& best() const { return best_; }
  /// Residuals and Jacobian at x, when the last Jacobian evaluation was complete there.
  bool jacobian_at(const VectorXd& x, VectorXd& r, MatrixXd& J) const {
    if (!jacobian_started_ || x != jacobian_point_ ||
        jacobian_blocks_ != static_cast<int>(jacobian_done_.size()))
      return false;
    r = r_;
    J = J_;
    return true;
  }

 private:
  void finish_point() {
    if (cost_started_ && cost_blocks_ == static_cast<int>(cost_done_.size()) &&
        std::isfinite(cost_sum_))
      best_.offer(cost_point_, 0.5 * cost_sum_);
  }
  std::mutex mutex_;
  int k_;
  VectorXd cost_point_;
  std::vector<char> cost_done_;
  bool cost_started_ = false;
  int cost_blocks_ = 0;
  double cost_sum_ = 0;
  VectorXd jacobian_point_;
  std::vector<char> jacobian_done_;
  bool jacobian_started_ = false;
  int jacobian_blocks_ = 0;
  VectorXd r_;
  MatrixXd J_;
  detail::BestPoint best_;
};

// One residual block of our problem as a Ceres cost function over the single parameter block
// x. Our Jacobian rows are column-major; Ceres wants row-major, hence the scratch copy.
class BlockCost final : public ceres::CostFunction {
 public:
  BlockCost(const LeastSquaresProblem& problem, int block, FailureLog& failures,
            EvaluationLog& evaluations)
      : problem_(problem), block_(block), failures_(failures), evaluations_(evaluations) {
    set_num_residuals(problem.residuals_per_block());
    mutable_parameter_block_sizes()->push_back(problem.num_parameters());
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    struct Scratch {
      VectorXd x;
      MatrixXd J;
    };
    thread_local Scratch scratch;
    const int n = problem_.num_parameters(), k = problem_.residuals_per_block();
    scratch.x = Eigen::Map<const VectorXd>(parameters[0], n);
    Eigen::Map<VectorXd> r(residuals, k);
    std::string why;
    bool ok;
    if (jacobians && jacobians[0]) {
      scratch.J.resize(k, n);
      Eigen::Ref<MatrixXd> J(scratch.J);
      ok = problem_.evaluate_block(block_, scratch.x, r, &J, &why);
      if (ok)
        Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            jacobians[0], k, n) = scratch.J;
      if (ok && r.allFinite()) evaluations_.add(block_, scratch.x, r, &scratch.J);
    } else {
      ok = problem_.evaluate_block(block_, scratch.x, r, nullptr, &why);
      if (ok && r.allFinite()) evaluations_.add(block_, scratch.x, r, nullptr);
    }
    if (!ok) {
      failures_.add(why);
      return false;
    }
    // Non-finite values: Ceres would reject the evaluation the same way, after a glog
    // warning (see the top of this file).
    if (!r.allFinite()) return false;
    if (jacobians && jacobians[0] && !scratch.J.allFinite()) return false;
    return true;
  }

 private:
  const LeastSquaresProblem& problem_;
  int block_;
  FailureLog& failures_;
  EvaluationLog& evaluations_;
};

// The loss Ceres sees: scale * rho (rho the robust loss, or s without one), a scale that
// the backend sets before each run of Ceres (detail::objective_scale). What ceres::ScaledLoss
// does, with a scale that can change between runs.
class NormalizedLoss final : public ceres::LossFunction {
 public:
  explicit NormalizedLoss(const ceres::LossFunction* robust) : robust_(robust) {}
  void set_scale(double scale) { scale_ = scale; }
  double scale() const { return scale_; }
  void Evaluate(double s, double rho[3]) const override {
    if (robust_) {
      robust_->Evaluate(s, rho);
    } else {
      rho[0] = s;
      rho[1] = 1;
      rho[2] = 0;
    }
    for (int i = 0; i < 3; ++i) rho[i] *= scale_;
  }

 private:
  const ceres::LossFunction* robust_;
  double scale_ = 1;
};

// Records accepted iterates in our trace and forwards them to the user's callback. Ceres
// calls it after every iteration, so it also counts the trailing run of trial points whose
// residuals could not be computed (Ceres treats them as rejected steps). It also runs kincal's
// gradient test at every iterate (stationarity.hpp), in place of Ceres' own, which compares
// max|J^T r| with an absolute number: that scales with the square of the residuals' unit, and
// with a model's reading_std of 1e8 it fired at the start (issue 35).
class TraceCallback final : public ceres::IterationCallback {
 public:
  TraceCallback(detail::SolveMonitor& monitor, FailureLog& failures, const EvaluationLog& log,
                const RobustLoss& loss, const NormalizedLoss& normalized,
                const SolverOptions& options, const double* x, int n)
      : monitor_(monitor),
        failures_(failures),
        log_(log),
        loss_(loss),
        normalized_(normalized),
        options_(options),
        x_(x),
        n_(n) {}

  /// A later run of Ceres continues the trace: its iterations are numbered after `iterations`
  /// and its iteration 0, the last iterate of the run before, is already recorded.
  void continue_after(int iterations) { offset_ = iterations; }

  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    const int failed = failures_.total();
    uncomputable_trials_ =
        failed > failures_seen_ && !s.step_is_successful ? uncomputable_trials_ + 1 : 0;
    failures_seen_ = failed;
    if (s.iteration > 0 && !s.step_is_successful) return ceres::SOLVER_CONTINUE;
    if (s.iteration == 0 && offset_ > 0) return ceres::SOLVER_CONTINUE;
    IterationRecord record;
    record.iteration = s.iteration + offset_;
    record.cost = s.cost / normalized_.scale();  // Ceres' are of scale * cost
    record.gradient_norm = s.gradient_max_norm / normalized_.scale();
    record.step_norm = s.step_norm;
    record.damping = s.trust_region_radius;
    // update_state_every_iteration makes x the current iterate here.
    current_ = Eigen::Map<const VectorXd>(x_, n_);
    if (!monitor_.record(record, current_)) {
      stopped_ = true;
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    // Ceres evaluates the Jacobian at an accepted iterate before it calls back.
    if (log_.jacobian_at(current_, r_, J_)) {
      row_scale_.resize(r_.size());
      loss_.correct(r_, J_, row_scale_);
      if (relative_gradient(current_, r_, J_, options_) <= options_.gradient_tolerance) {
        stationary_ = true;
        return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
      }
    }
    return ceres::SOLVER_CONTINUE;
  }
  bool stopped() const { return stopped_; }
  /// The iterate passed kincal's gradient test (the solve ends USER_SUCCESS).
  bool stationary() const { return stationary_; }
  /// Trial points at the end of the solve whose residuals could not be computed, including
  /// a last one Ceres evaluated without reporting the iteration (its step tests end the
  /// solve before the callbacks run).
  int trailing_uncomputable_trials() {
    return failures_.total() > failures_seen_ ? uncomputable_trials_ + 1 : uncomputable_trials_;
  }

 private:
  detail::SolveMonitor& monitor_;
  FailureLog& failures_;
  const EvaluationLog& log_;
  const RobustLoss& loss_;
  const NormalizedLoss& normalized_;
  const SolverOptions& options_;
  int offset_ = 0;
  int failures_seen_ = 0;
  int uncomputable_trials_ = 0;
  const double* x_;
  int n_;
  VectorXd current_, r_, row_scale_;
  MatrixXd J_;
  bool stopped_ = false, stationary_ = false;
};

const std::vector<std::string> kTrustRegions = {"levenberg_marquardt", "dogleg"};
const std::vector<std::string> kDoglegTypes = {"traditional", "subspace"};
const std::vector<std::string> kLinearSolvers = {"dense_qr",    "dense_normal_cholesky",
                                                 "dense_schur", "sparse_normal_cholesky",
                                                 "cgnr",        "iterative_schur"};

class CeresSolver final : public Solver {
 public:
  std::string name() const override { return "ceres"; }

  void check_options(const SolverOptions& options) const override {
    Solver::check_options(options);
    std::string error;
    if (!ceres_options(options, 1).IsValid(&error)) throw InvalidSolverOptions("ceres: " + error);
  }
  std::unique_ptr<BackendSettings> default_settings() const override {
    return std::make_unique<CeresSettings>();
  }
  bool takes_robust_loss() const override { return true; }

  Summary solve(const LeastSquaresProblem& problem, VectorXd& x,
                const SolverOptions& options) const override {
    check_options(options);
    check_sizes(problem, x, options);
    Summary summary;
    summary.solver = name();
    detail::SolveMonitor monitor(options, summary);

    const int n = problem.num_parameters();
    // Ceres requires a feasible start; the check below must see the point Ceres starts from.
    if (options.lower_bounds && options.upper_bounds)
      x = x.cwiseMax(*options.lower_bounds).cwiseMin(*options.upper_bounds);

    // Residuals or a Jacobian that cannot be computed at the start are our failure, reported
    // with our reason, before Ceres sees the problem (Ceres would only say that an evaluation
    // failed).
    const RobustLoss& loss = options.loss;
    // The scale of what Ceres sees at `at` (r, J there): detail::objective_scale of the
    // robust-corrected Jacobian, every column of norm >= 1. Ceres' Jacobi scaling
    // 1 / (1 + |J_j|), its bounds on the LM diagonal and its projected gradient then meet the
    // same numbers whatever the common scale of the residuals.
    auto scale_at = [&](VectorXd r, MatrixXd J) {
      VectorXd row_scale(r.size());
      loss.correct(r, J, row_scale);
      return detail::objective_scale(J, detail::ScaleBy::kSmallestColumn);
    };
    double scale = 1;
    {
      std::string why;
      VectorXd r;
      MatrixXd J;
      ++summary.residual_evaluations;
      ++summary.jacobian_evaluations;
      std::string failure;
      if (!problem.evaluate(x, &r, &J, &why, options.num_threads))
        failure = "residuals not computable at the start: " + why;
      else
        failure = detail::non_finite_start(r, &J, problem.parameter_names());
      if (!failure.empty()) {
        summary.initial_cost = summary.final_cost = std::numeric_limits<double>::infinity();
        monitor.finish(TerminationType::kFailed, failure);
        return summary;
      }
      scale = scale_at(r, J);
    }

    ceres::Problem::Options problem_options;
    // One loss object serves every block; the problem must not delete it per block.
    problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem ceres_problem(problem_options);
    std::unique_ptr<ceres::LossFunction> robust;
    if (loss.kind == RobustLoss::Kind::kHuber)
      robust = std::make_unique<ceres::HuberLoss>(loss.delta);
    else if (loss.kind == RobustLoss::Kind::kCauchy)
      robust = std::make_unique<ceres::CauchyLoss>(loss.delta);
    // Ceres sees scale * rho: the same minimum, at a scale that does not depend on the
    // residuals' unit or the loss's delta (a power of two: exact).
    NormalizedLoss normalized(robust.get());

    FailureLog failures;
    EvaluationLog evaluations(problem.num_residual_blocks(), problem.residuals_per_block(), n);
    for (int b = 0; b < problem.num_residual_blocks(); ++b)
      ceres_problem.AddResidualBlock(new BlockCost(problem, b, failures, evaluations), &normalized,
                                     x.data());
    if (options.lower_bounds && options.upper_bounds) {
      for (int i = 0; i < n; ++i) {
        ceres_problem.SetParameterLowerBound(x.data(), i, (*options.lower_bounds)[i]);
        ceres_problem.SetParameterUpperBound(x.data(), i, (*options.upper_bounds)[i]);
      }
    }

    // Threads only for a problem large enough to pay for them, as in kincal's own evaluation:
    // Ceres sums the cost over threads in an order that varies from run to run, so a small
    // problem stays bit-for-bit reproducible.
    const int threads =
        std::min(options.num_threads, problem.num_residual_blocks() / kMinBlocksPerCeresThread);
    ceres::Solver::Options ceres_opts = ceres_options(options, threads);
    TraceCallback trace(monitor, failures, evaluations, loss, normalized, options, x.data(), n);
    ceres_opts.callbacks.push_back(&trace);
    ceres_opts.update_state_every_iteration = true;
    ceres::Solver::Summary ceres_summary;
    // Ceres' own gradient test (tolerance 0) fires only when its projected gradient
    // x - (x - g) rounds to 0, i.e. when g is below the rounding of x. That happens before a
    // minimum when the scale set at the start no longer fits, the Jacobian having shrunk by
    // orders of magnitude on the way (the test suite's far starts): when the point is not
    // stationary, Ceres goes on from there at the scale of that point, while iterations remain
    // (a few times at most).
    constexpr int kMaxRuns = 4;
    for (int run = 0;; ++run) {
      normalized.set_scale(scale);
      ceres_opts.max_num_iterations = options.max_iterations - summary.iterations;
      trace.continue_after(summary.iterations);
      ceres::Solve(ceres_opts, &ceres_problem, &ceres_summary);
      if (run == 0) summary.initial_cost = ceres_summary.initial_cost / scale;
      // Like lm: every trial step counts as an iteration, accepted or not.
      summary.iterations += std::max(0, static_cast<int>(ceres_summary.iterations.size()) - 1);
      summary.residual_evaluations += std::max(0, ceres_summary.num_residual_evaluations);
      summary.jacobian_evaluations += std::max(0, ceres_summary.num_jacobian_evaluations);
      VectorXd r;
      MatrixXd J;
      if (run + 1 >= kMaxRuns || summary.iterations >= options.max_iterations || trace.stopped() ||
          trace.stationary() || ceres_summary.termination_type != ceres::CONVERGENCE ||
          ceres_summary.message.rfind("Gradient tolerance", 0) != 0 ||
          !evaluations.jacobian_at(x, r, J))
        break;
      const double next = scale_at(r, J);
      VectorXd row_scale(r.size());
      loss.correct(r, J, row_scale);
      if (next == scale || measure_stationarity(x, r, J, options).claim_holds(options, false))
        break;
      scale = next;
    }
    summary.backend_code = static_cast<int>(ceres_summary.termination_type);
    summary.final_cost = ceres_summary.final_cost / scale;
    TerminationType type = termination(ceres_summary, trace.stopped());
    std::string message = ceres_summary.message;
    if (trace.stationary()) {
      type = TerminationType::kConverged;
      message = std::string(detail::kGradientTestMessage) +
                " (kincal's test, at Ceres' iterate: Ceres' own gradient test is absolute)";
    }
    if (failures.count > 0) {
      message += " (residuals failed at " + std::to_string(failures.count) +
                 " block evaluations; first: " + failures.first + ")";
      // Ceres shrinks the trust region around uncomputable trial points until its step or
      // radius test fires and calls that convergence; like lm, we call it leaving the region
      // where the residuals exist. So is a Ceres FAILURE caused by them after the start.
      const int trailing = trace.trailing_uncomputable_trials();
      if ((type == TerminationType::kConverged && trailing > 0) ||
          (type == TerminationType::kFailed && trailing > 0 && !ceres_summary.iterations.empty())) {
        type = TerminationType::kDiverged;
        message = std::to_string(trailing) +
                  " consecutive trial points at the end where residuals could not be computed; "
                  "Ceres: " +
                  message;
      }
    }
    // Return the best point evaluated, unless it is lower than Ceres' final point by no more
    // than the cost's rounding error, with its true cost (after a FAILURE Ceres' final_cost
    // need not be the cost of the parameters it leaves), and check a convergence claim where
    // we return. With a robust loss Ceres' costs are robustified and none of this applies.
    evaluations.finish();
    if (loss.kind == RobustLoss::Kind::kNone) {
      VectorXd r;
      MatrixXd J;
      bool known = evaluations.jacobian_at(x, r, J);
      if (!known) {
        ++summary.residual_evaluations;
        ++summary.jacobian_evaluations;
        known = problem.evaluate(x, &r, &J, nullptr, options.num_threads);
      }
      double cost = known ? 0.5 * r.squaredNorm() : std::numeric_limits<double>::infinity();
      const double noise = known ? cost_rounding(x, r, J) : 0.0;
      if (evaluations.best().cost() < cost - noise) {
        x = evaluations.best().x();
        cost = evaluations.best().cost();
        known = false;
        if (type == TerminationType::kConverged) {
          ++summary.residual_evaluations;
          ++summary.jacobian_evaluations;
          known = problem.evaluate(x, &r, &J, nullptr, options.num_threads);
        }
      }
      summary.final_cost = cost;
      if (type == TerminationType::kConverged && known) {
        const detail::Verdict verdict = detail::judge_convergence(
            measure_stationarity(x, r, J, options), options, message, problem.parameter_names(),
            trace.trailing_uncomputable_trials() > 0);
        type = verdict.type;
        message = verdict.message;
      }
    }
    monitor.finish(type, message);
    return summary;
  }

 private:
  ceres::Solver::Options ceres_options(const SolverOptions& options, int threads) const {
    ceres::Solver::Options o;
    o.max_num_iterations = options.max_iterations;
    o.function_tolerance = options.function_tolerance;
    o.parameter_tolerance = options.parameter_tolerance;
    // Ceres' gradient test compares max|J^T r| with an absolute number; kincal's, relative to
    // |J_j| |r|, runs in the iteration callback instead (TraceCallback).
    o.gradient_tolerance = 0;
    o.num_threads = std::max(1, threads);
    o.logging_type = ceres::SILENT;
    o.minimizer_progress_to_stdout = false;
    const CeresSettings settings = settings_for<CeresSettings>(name(), options);
    o.trust_region_strategy_type =
        settings.trust_region == "dogleg" ? ceres::DOGLEG : ceres::LEVENBERG_MARQUARDT;
    o.dogleg_type =
        settings.dogleg_type == "subspace" ? ceres::SUBSPACE_DOGLEG : ceres::TRADITIONAL_DOGLEG;
    ceres::StringToLinearSolverType(settings.linear_solver, &o.linear_solver_type);
    o.initial_trust_region_radius = settings.initial_trust_region_radius;
    return o;
  }

  static TerminationType termination(const ceres::Solver::Summary& s, bool user_stopped) {
    switch (s.termination_type) {
      case ceres::CONVERGENCE:
        return TerminationType::kConverged;
      case ceres::NO_CONVERGENCE:
        return TerminationType::kMaxIterations;
      case ceres::USER_SUCCESS:
        return user_stopped ? TerminationType::kUserStopped : TerminationType::kConverged;
      case ceres::USER_FAILURE:
      case ceres::FAILURE:
        return TerminationType::kFailed;
    }
    return TerminationType::kFailed;
  }
};

}  // namespace

const std::vector<SettingField<CeresSettings>>& CeresSettings::fields() {
  using S = CeresSettings;
  static const std::vector<SettingField<S>> fields = {
      {"trust_region", &S::trust_region, kTrustRegions},
      {"dogleg_type", &S::dogleg_type, kDoglegTypes},
      {"linear_solver", &S::linear_solver, kLinearSolvers},
      {"initial_trust_region_radius", &S::initial_trust_region_radius}};
  return fields;
}

std::unique_ptr<Solver> make_ceres_solver() { return std::make_unique<CeresSolver>(); }

}  // namespace kincal
