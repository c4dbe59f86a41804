#include "kincal/solvers/ipopt_solver.hpp"

#include <coin/IpIpoptApplication.hpp>
#include <coin/IpIpoptCalculatedQuantities.hpp>
#include <coin/IpIpoptData.hpp>
#include <coin/IpOrigIpoptNLP.hpp>
#include <coin/IpTNLP.hpp>
#include <coin/IpTNLPAdapter.hpp>
// Ipopt 3.11 loads the HSL solvers from libhsl.so and Pardiso from libpardiso.so at run time
// (Debian's build has only MUMPS inside); these loaders let us check before solving.
#if __has_include(<coin/HSLLoader.h>) && __has_include(<coin/PardisoLoader.h>)
#include <coin/HSLLoader.h>
#include <coin/PardisoLoader.h>
#define KINCAL_IPOPT_HAS_SOLVER_LOADERS 1
#endif

#include <cmath>
#include <limits>
#include <mutex>

#include "kincal/solvers/solver_common.hpp"

namespace kincal {
namespace {

using Ipopt::Index;
using Ipopt::Number;

// Ipopt reads bounds beyond +-1e19 as absent.
constexpr double kNoBound = 2e19;

const char* status_name(Ipopt::ApplicationReturnStatus status) {
  switch (status) {
    case Ipopt::Solve_Succeeded:
      return "Solve_Succeeded";
    case Ipopt::Solved_To_Acceptable_Level:
      return "Solved_To_Acceptable_Level";
    case Ipopt::Infeasible_Problem_Detected:
      return "Infeasible_Problem_Detected";
    case Ipopt::Search_Direction_Becomes_Too_Small:
      return "Search_Direction_Becomes_Too_Small";
    case Ipopt::Diverging_Iterates:
      return "Diverging_Iterates";
    case Ipopt::User_Requested_Stop:
      return "User_Requested_Stop";
    case Ipopt::Feasible_Point_Found:
      return "Feasible_Point_Found";
    case Ipopt::Maximum_Iterations_Exceeded:
      return "Maximum_Iterations_Exceeded";
    case Ipopt::Restoration_Failed:
      return "Restoration_Failed";
    case Ipopt::Error_In_Step_Computation:
      return "Error_In_Step_Computation";
    case Ipopt::Maximum_CpuTime_Exceeded:
      return "Maximum_CpuTime_Exceeded";
    case Ipopt::Not_Enough_Degrees_Of_Freedom:
      return "Not_Enough_Degrees_Of_Freedom";
    case Ipopt::Invalid_Problem_Definition:
      return "Invalid_Problem_Definition";
    case Ipopt::Invalid_Option:
      return "Invalid_Option";
    case Ipopt::Invalid_Number_Detected:
      return "Invalid_Number_Detected";
    case Ipopt::Unrecoverable_Exception:
      return "Unrecoverable_Exception";
    case Ipopt::NonIpopt_Exception_Thrown:
      return "NonIpopt_Exception_Thrown";
    case Ipopt::Insufficient_Memory:
      return "Insufficient_Memory";
    case Ipopt::Internal_Error:
      return "Internal_Error";
  }
  return "unknown status";
}

// Statuses with which Ipopt gives up on finding a step: at the edge of the region where the
// residuals exist (trial points failing) that means the iterates kept leaving it.
bool gave_up_on_the_step(Ipopt::ApplicationReturnStatus status) {
  return status == Ipopt::Restoration_Failed || status == Ipopt::Error_In_Step_Computation ||
         status == Ipopt::Search_Direction_Becomes_Too_Small ||
         status == Ipopt::Invalid_Number_Detected;
}

// Empty when Ipopt can use `linear_solver`, else why not. MUMPS is linked in; the others
// need a library Ipopt loads at run time, and without it Ipopt only says Invalid_Option
// (and for ma97 prints to stdout). Loading is process-wide, hence the lock.
std::string linear_solver_unavailable(const std::string& linear_solver) {
  if (linear_solver == "mumps") return "";
#ifdef KINCAL_IPOPT_HAS_SOLVER_LOADERS
  static std::mutex mutex;
  std::lock_guard<std::mutex> lock(mutex);
  char message[512] = "";
  if (linear_solver == "pardiso") {
    if (LSL_isPardisoLoaded() || LSL_loadPardisoLib(nullptr, message, sizeof message) == 0)
      return "";
    return std::string("Ipopt could not load ") + LSL_PardisoLibraryName() + ": " + message;
  }
  if (!LSL_isHSLLoaded() && LSL_loadHSL(nullptr, message, sizeof message) != 0)
    return std::string("Ipopt could not load ") + LSL_HSLLibraryName() + ": " + message;
  const bool found = (linear_solver == "ma27" && LSL_isMA27available()) ||
                     (linear_solver == "ma57" && LSL_isMA57available()) ||
                     (linear_solver == "ma77" && LSL_isMA77available()) ||
                     (linear_solver == "ma86" && LSL_isMA86available()) ||
                     (linear_solver == "ma97" && LSL_isMA97available());
  return found ? "" : std::string(LSL_HSLLibraryName()) + " does not provide it";
#else
  return "";  // no loader API to ask: Ipopt will end Invalid_Option if it cannot load it
#endif
}

// Against the edge of the region where the residuals exist, Ipopt cuts every step back to
// ~1e-16 and repeats until max_iter (measured on a fenced curve fit: ~46 failed evaluations
// per iteration, 100 iterations in 0.1 s for nothing). This many iterations in a row without
// a cost change while trial points fail end the solve as `diverged` (lm's max_invalid_steps
// default is also 10).
constexpr int kMaxStuckIterations = 10;

// The least-squares problem as an Ipopt NLP: variables x, no constraints, f = 1/2 |r|^2.
// Residuals and Jacobian are cached per x: Ipopt asks for f, its gradient and the Hessian at
// the same point in separate calls.
class LeastSquaresNlp final : public Ipopt::TNLP {
 public:
  LeastSquaresNlp(const LeastSquaresProblem& problem, const SolverOptions& options,
                  Summary& summary, detail::SolveMonitor& monitor, const VectorXd& x0,
                  bool exact_hessian)
      : problem_(problem),
        options_(options),
        summary_(summary),
        monitor_(monitor),
        x0_(x0),
        exact_hessian_(exact_hessian),
        n_(static_cast<int>(x0.size())) {}

  // Evaluates at x (with the Jacobian when asked) unless the cache already holds it.
  // Returns false when the residuals cannot be computed there; the reason is in why().
  bool evaluate(const VectorXd& x, bool with_jacobian) {
    if (cache_valid_ && x == cached_x_ && (has_jacobian_ || !with_jacobian)) return cache_ok_;
    cached_x_ = x;
    cache_valid_ = true;
    has_jacobian_ = with_jacobian;
    ++summary_.residual_evaluations;
    if (with_jacobian) ++summary_.jacobian_evaluations;
    cache_ok_ =
        problem_.evaluate(x, &r_, with_jacobian ? &J_ : nullptr, &why_, options_.num_threads);
    non_finite_ = false;
    if (cache_ok_) {
      // A non-finite value is no cost and no gradient for Ipopt, and our tests cannot judge a
      // point with one (issue 35: a NaN Jacobian at the start was reported converged).
      const MatrixXd* J = with_jacobian ? &J_ : nullptr;
      non_finite_ = !r_.allFinite() || (J && !J->allFinite());
      if (non_finite_) why_ = detail::non_finite_entry(r_, J, problem_.parameter_names());
      cache_ok_ = !non_finite_;
    }
    if (cache_ok_ && with_jacobian) gradient_.noalias() = J_.transpose() * r_;
    if (cache_ok_) offer_best(x, with_jacobian);
    // Ipopt only hears "false" and cuts its step back; the reason would be lost.
    if (!cache_ok_ && failures_++ == 0) first_failure_ = why_;
    last_failed_ = !cache_ok_;
    return cache_ok_;
  }
  double cost() const { return 0.5 * r_.squaredNorm(); }
  const VectorXd& gradient() const { return gradient_; }
  const std::string& why() const { return why_; }
  /// The last evaluation computed a non-finite residual or Jacobian entry.
  bool non_finite() const { return non_finite_; }
  /// Points (trial points included) where the residuals could not be computed, the first
  /// reason, and whether the most recent evaluation was one of them.
  int failures() const { return failures_; }
  const std::string& first_failure() const { return first_failure_; }
  bool last_failed() const { return last_failed_; }

  bool stopped_by_callback() const { return stopped_by_callback_; }
  /// The run ended because an iterate passed one of kincal's tests, named by passed_test().
  bool stopped_stationary() const { return stopped_stationary_; }
  const std::string& passed_test() const { return passed_test_; }
  /// Ipopt was stopped because its iterates had stalled against uncomputable trial points.
  bool stuck() const { return stuck_iterations_ >= kMaxStuckIterations; }
  int last_iteration() const { return last_iteration_; }
  /// The lowest-cost point evaluated (the start included), whatever Ipopt ends on: what we
  /// return. Its residuals and Jacobian, when they were evaluated there.
  const VectorXd& best_x() const { return best_x_; }
  double best_cost() const { return best_cost_; }
  bool best_jacobian(VectorXd& r, MatrixXd& J) const {
    if (!best_has_jacobian_) return false;
    r = best_r_;
    J = best_J_;
    return true;
  }
  /// Residuals and Jacobian at x when an evaluation there is at hand (the last one, or the
  /// best point's).
  bool jacobian_at(const VectorXd& x, VectorXd& r, MatrixXd& J) const {
    if (cache_valid_ && cache_ok_ && has_jacobian_ && cached_x_ == x) {
      r = r_;
      J = J_;
      return true;
    }
    return x == best_x_ && best_jacobian(r, J);
  }
  bool finalized() const { return finalized_; }
  const VectorXd& final_x() const { return final_x_; }
  double final_cost() const { return final_cost_; }

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag,
                    IndexStyleEnum& index_style) override {
    n = n_;
    m = 0;
    nnz_jac_g = 0;
    nnz_h_lag = exact_hessian_ ? n_ * (n_ + 1) / 2 : 0;
    index_style = C_STYLE;
    return true;
  }

  bool get_bounds_info(Index n, Number* x_l, Number* x_u, Index, Number*, Number*) override {
    for (Index i = 0; i < n; ++i) {
      x_l[i] = options_.lower_bounds ? (*options_.lower_bounds)[i] : -kNoBound;
      x_u[i] = options_.upper_bounds ? (*options_.upper_bounds)[i] : kNoBound;
    }
    return true;
  }

  bool get_starting_point(Index n, bool init_x, Number* x, bool, Number*, Number*, Index, bool,
                          Number*) override {
    if (init_x) Eigen::Map<VectorXd>(x, n) = x0_;
    return true;
  }

  bool eval_f(Index n, const Number* x, bool, Number& obj_value) override {
    // With the Gauss-Newton Hessian nearly every trial point is accepted, and Ipopt then
    // asks for the gradient there: getting J now saves evaluating the residuals twice.
    if (!evaluate(Eigen::Map<const VectorXd>(x, n), exact_hessian_)) return false;
    obj_value = cost();
    return true;
  }

  bool eval_grad_f(Index n, const Number* x, bool, Number* grad_f) override {
    if (!evaluate(Eigen::Map<const VectorXd>(x, n), true)) return false;
    Eigen::Map<VectorXd>(grad_f, n) = gradient_;
    return true;
  }

  bool eval_g(Index, const Number*, bool, Index, Number*) override { return true; }

  bool eval_jac_g(Index, const Number*, bool, Index, Index, Index*, Index*, Number*) override {
    return true;
  }

  // Hessian of the Lagrangian = obj_factor * J^T J (no constraints), dense lower triangle.
  bool eval_h(Index n, const Number* x, bool, Number obj_factor, Index, const Number*, bool, Index,
              Index* i_row, Index* j_col, Number* values) override {
    if (values == nullptr) {
      Index k = 0;
      for (Index i = 0; i < n; ++i)
        for (Index j = 0; j <= i; ++j, ++k) {
          i_row[k] = i;
          j_col[k] = j;
        }
      return true;
    }
    if (!evaluate(Eigen::Map<const VectorXd>(x, n), true)) return false;
    jtj_.setZero(n, n);
    jtj_.selfadjointView<Eigen::Lower>().rankUpdate(J_.transpose(), obj_factor);
    Index k = 0;
    for (Index i = 0; i < n; ++i)
      for (Index j = 0; j <= i; ++j) values[k++] = jtj_(i, j);
    return true;
  }

  bool intermediate_callback(Ipopt::AlgorithmMode mode, Index iter, Number obj_value, Number,
                             Number, Number mu, Number, Number, Number, Number, Index,
                             const Ipopt::IpoptData* ip_data,
                             Ipopt::IpoptCalculatedQuantities* ip_cq) override {
    // Restoration-phase iterates belong to another problem; there are no constraints to
    // restore here anyway.
    if (mode != Ipopt::RegularMode || !current_x(ip_data, ip_cq)) return true;
    last_iteration_ = iter;
    const bool have_gradient = cache_valid_ && cache_ok_ && has_jacobian_ && cached_x_ == x_;
    const double gradient_norm = have_gradient ? gradient_.lpNorm<Eigen::Infinity>() : 0.0;
    const double step = previous_x_.size() == x_.size() ? (x_ - previous_x_).norm() : 0.0;
    previous_x_ = x_;
    if (!monitor_.record({iter, obj_value, gradient_norm, step, mu, 0}, x_)) {
      stopped_by_callback_ = true;
      return false;
    }
    if (stuck_at_the_edge(iter, obj_value)) return false;
    // Stop once the iterate passes one of our tests without their rounding allowances (Ipopt's
    // own are absolute; Stationarity::settled): with them, the cost test holds near a noisy
    // minimum while the Gauss-Newton step still moves the parameters by ~1e-5 mm, and Ipopt's
    // next steps, Newton's on J^T J, are that step. The claim is then judged with them.
    if (cache_valid_ && cache_ok_ && has_jacobian_ && cached_x_ == x_) {
      measure_stationarity(x_, r_, J_, options_, scratch_, at_x_);
      if (at_x_.settled(options_) && at_x_.claim_holds(options_, false)) {
        passed_test_ = detail::passing_test(at_x_, options_);
        stopped_stationary_ = true;
        return false;
      }
    }
    return true;
  }

  void finalize_solution(Ipopt::SolverReturn, Index n, const Number* x, const Number*,
                         const Number*, Index, const Number*, const Number*, Number obj_value,
                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    if (x == nullptr) return;
    finalized_ = true;
    final_x_ = Eigen::Map<const VectorXd>(x, n);
    final_cost_ = obj_value;
  }

 private:
  // Ipopt 3.11 does not hand the current iterate to the callback (3.14's GetCurrentIterate);
  // the TNLPAdapter can map its internal vector back to ours.
  bool current_x(const Ipopt::IpoptData* ip_data, Ipopt::IpoptCalculatedQuantities* ip_cq) {
    if (ip_data == nullptr || ip_cq == nullptr) return false;
    auto* orig = dynamic_cast<Ipopt::OrigIpoptNLP*>(Ipopt::GetRawPtr(ip_cq->GetIpoptNLP()));
    if (orig == nullptr) return false;
    auto* adapter = dynamic_cast<Ipopt::TNLPAdapter*>(Ipopt::GetRawPtr(orig->nlp()));
    if (adapter == nullptr) return false;
    x_.resize(n_);
    adapter->ResortX(*ip_data->curr()->x(), x_.data());
    return true;
  }

  void offer_best(const VectorXd& x, bool with_jacobian) {
    // Ipopt relaxes the bounds by bound_relax_factor (1e-8) and may evaluate just outside
    // them; only points inside the box can be returned.
    if (options_.lower_bounds && ((x.array() < options_.lower_bounds->array()).any() ||
                                  (x.array() > options_.upper_bounds->array()).any()))
      return;
    const double cost = 0.5 * r_.squaredNorm();
    const bool better = cost < best_cost_;
    if (!better && !(with_jacobian && !best_has_jacobian_ && x == best_x_)) return;
    best_cost_ = cost;
    best_x_ = x;
    best_r_ = r_;
    best_has_jacobian_ = with_jacobian;
    if (with_jacobian) best_J_ = J_;
  }

  const LeastSquaresProblem& problem_;
  const SolverOptions& options_;
  Summary& summary_;
  detail::SolveMonitor& monitor_;
  VectorXd x0_;
  const bool exact_hessian_;
  const int n_;

  // An iteration whose cost did not change while trial points failed is "stuck".
  bool stuck_at_the_edge(Index iter, double cost) {
    const bool failing = failures_ > failures_at_last_iteration_;
    failures_at_last_iteration_ = failures_;
    const bool flat =
        iter > 0 && detail::small_cost_change(previous_cost_, cost, options_.function_tolerance);
    previous_cost_ = cost;
    stuck_iterations_ = failing && flat ? stuck_iterations_ + 1 : 0;
    return stuck();
  }
  int failures_at_last_iteration_ = 0;
  double previous_cost_ = 0;
  int stuck_iterations_ = 0;

  bool cache_valid_ = false, cache_ok_ = false, has_jacobian_ = false;
  VectorXd cached_x_, r_, gradient_;
  MatrixXd J_, jtj_;
  std::string why_;
  bool non_finite_ = false;
  int failures_ = 0;
  std::string first_failure_;
  bool last_failed_ = false;

  VectorXd x_, previous_x_;
  int last_iteration_ = 0;
  bool stopped_by_callback_ = false;
  bool stopped_stationary_ = false;
  std::string passed_test_;
  StationarityScratch scratch_{problem_.num_residuals(), problem_.num_parameters()};
  Stationarity at_x_;
  double best_cost_ = std::numeric_limits<double>::infinity();
  VectorXd best_x_, best_r_;
  MatrixXd best_J_;
  bool best_has_jacobian_ = false;
  bool finalized_ = false;
  VectorXd final_x_;
  double final_cost_ = std::numeric_limits<double>::infinity();
};

class IpoptSolver final : public Solver {
 public:
  std::string name() const override { return "ipopt"; }
  std::unique_ptr<BackendSettings> default_settings() const override {
    return std::make_unique<IpoptSettings>();
  }

  void check_options(const SolverOptions& options) const override {
    Solver::check_options(options);
    const std::string linear = linear_solver(options);
    const std::string why = linear_solver_unavailable(linear);
    if (!why.empty())
      throw InvalidSolverOptions("ipopt: linear_solver=" + linear + " is not available: " + why +
                                 " (Debian's Ipopt has only MUMPS built in: use "
                                 "linear_solver=mumps, the default)");
  }

  Summary solve(const LeastSquaresProblem& problem, VectorXd& x,
                const SolverOptions& options) const override {
    check_options(options);
    check_sizes(problem, x, options);
    Summary summary;
    summary.solver = name();
    detail::SolveMonitor monitor(options, summary);
    if (options.lower_bounds) x = x.cwiseMax(*options.lower_bounds).cwiseMin(*options.upper_bounds);

    const bool exact_hessian = hessian(options) == "gauss-newton";
    Ipopt::SmartPtr<LeastSquaresNlp> nlp =
        new LeastSquaresNlp(problem, options, summary, monitor, x, exact_hessian);
    // Check the start ourselves: Ipopt would only say Invalid_Number_Detected.
    if (!nlp->evaluate(x, true)) {
      summary.initial_cost = summary.final_cost = std::numeric_limits<double>::infinity();
      monitor.finish(TerminationType::kFailed,
                     nlp->non_finite() ? detail::non_finite_start(nlp->why())
                                       : "residuals not computable at the start: " + nlp->why());
      return summary;
    }
    summary.initial_cost = summary.final_cost = nlp->cost();

    // Without a console journal Ipopt cannot print anything, banner included.
    const bool ipopt_output = options.verbosity > 1;
    Ipopt::SmartPtr<Ipopt::IpoptApplication> app = new Ipopt::IpoptApplication(ipopt_output);
    Ipopt::OptionsList& o = *app->Options();
    o.SetStringValue("sb", "yes");  // the banner
    o.SetIntegerValue("print_level", ipopt_output ? 5 : 0);
    o.SetIntegerValue("max_iter", options.max_iterations);
    // kincal's tests decide convergence, at every iterate (LeastSquaresNlp's callback stops
    // Ipopt as soon as one holds). Ipopt's own are absolute: its optimality error is max|J^T r|
    // unscaled (it fired at the start with a model's reading_std of 1e8, issue 35), and its
    // acceptable level compares the cost change with max(1, |f|), an absolute test below
    // f = 1 that stopped well short of ours (penalty functions, Powell singular: measured).
    // So its tolerance is set below anything a gradient reaches and its acceptable level off;
    // it still stops on an exactly zero gradient, its iteration limit and its failures, which
    // are judged at the point returned.
    o.SetStringValue("nlp_scaling_method", "none");
    // Ipopt minimises objective_scale * cost: its absolute constants (the first Hessian
    // perturbation, the barrier parameter) then meet the same problem whatever the residuals'
    // unit (detail::objective_scale).
    {
      VectorXd r;
      MatrixXd J;
      if (nlp->jacobian_at(x, r, J))
        o.SetNumericValue("obj_scaling_factor",
                          detail::objective_scale(J, detail::ScaleBy::kSmallestColumn));
    }
    o.SetNumericValue("tol", 1e-300);
    o.SetIntegerValue("acceptable_iter", 0);
    // Ipopt relaxes the bounds by 1e-8 by default, so its iterates may lie just outside them,
    // where we may not return: keep them inside (no effect without bounds).
    o.SetNumericValue("bound_relax_factor", 0);
    o.SetStringValue("hessian_approximation", exact_hessian ? "exact" : "limited-memory");
    o.SetStringValue("mu_strategy", mu_strategy(options));
    o.SetStringValue("linear_solver", linear_solver(options));

    // "" = do not read ./ipopt.opt: a stray file must not change our results.
    Ipopt::ApplicationReturnStatus status = app->Initialize("");
    if (status == Ipopt::Solve_Succeeded)
      status = app->OptimizeTNLP(Ipopt::SmartPtr<Ipopt::TNLP>(Ipopt::GetRawPtr(nlp)));

    summary.backend_code = static_cast<int>(status);
    summary.iterations = nlp->last_iteration();
    // Ipopt's final point, or the best point evaluated when that is lower by more than the
    // cost's rounding error (a failed line search can end far uphill: 1e299 from a start of
    // cost 0.39, measured).
    Endpoint end = endpoint(problem, *nlp, options, summary);
    x = end.x;
    summary.final_cost = end.cost;
    auto [type, message] = termination(status, nlp->stopped_by_callback());
    if (status == Ipopt::User_Requested_Stop && nlp->stopped_stationary()) {
      type = TerminationType::kConverged;
      message = nlp->passed_test() + " (kincal's test, at Ipopt's iterate)";
    }
    if (nlp->stuck()) {
      type = TerminationType::kDiverged;
      message = "stopped after " + std::to_string(kMaxStuckIterations) +
                " iterations without progress, every trial point beyond the region where "
                "the residuals can be computed";
    }
    if (nlp->failures() > 0) {
      message += " (residuals failed at " + std::to_string(nlp->failures()) +
                 " of the points Ipopt tried; first: " + nlp->first_failure() + ")";
      // Ipopt gives up (restoration failed, step too small, ...) at the edge of the region
      // where the residuals exist: as ceres and lm do, call that leaving the region.
      if (type == TerminationType::kFailed && nlp->last_failed() && gave_up_on_the_step(status))
        type = TerminationType::kDiverged;
    }
    // Ipopt's tests are not ours (its acceptable-level cost change is absolute below |f| = 1,
    // and it stops on a zero Jacobian): judge its claims, and its failures and iteration limit,
    // at the point returned.
    if (type == TerminationType::kConverged || type == TerminationType::kFailed ||
        type == TerminationType::kMaxIterations) {
      if (!end.known) {
        ++summary.residual_evaluations;
        ++summary.jacobian_evaluations;
        end.known = problem.evaluate(x, &end.r, &end.J, nullptr, options.num_threads);
      }
      if (end.known) {
        const Stationarity at_x = measure_stationarity(x, end.r, end.J, options);
        const auto names = problem.parameter_names();
        const detail::Verdict verdict =
            type == TerminationType::kConverged
                ? detail::judge_convergence(at_x, options, message, names, nlp->last_failed())
                : detail::judge_other_stop(at_x, options, type, message, names);
        type = verdict.type;
        message = verdict.message;
      }
    }
    monitor.finish(type, message);
    return summary;
  }

 private:
  // The point to return, with its cost and, when at hand, its residuals and Jacobian.
  struct Endpoint {
    VectorXd x, r;
    MatrixXd J;
    double cost = 0;
    bool known = false;
  };
  // Ipopt's final point (its last iterate), unless the best point evaluated is lower by more
  // than the cost's rounding error there; the best point when Ipopt left none.
  static Endpoint endpoint(const LeastSquaresProblem& problem, const LeastSquaresNlp& nlp,
                           const SolverOptions& options, Summary& summary) {
    Endpoint end;
    end.x = nlp.best_x();
    end.cost = nlp.best_cost();
    const VectorXd& last = nlp.final_x();
    const bool usable =
        nlp.finalized() && last.size() == end.x.size() && last.allFinite() &&
        (!options.lower_bounds || ((last.array() >= options.lower_bounds->array()).all() &&
                                   (last.array() <= options.upper_bounds->array()).all()));
    if (usable && last != nlp.best_x()) {
      VectorXd r;
      MatrixXd J;
      bool known = nlp.jacobian_at(nlp.final_x(), r, J);
      if (!known) {
        ++summary.residual_evaluations;
        ++summary.jacobian_evaluations;
        known = problem.evaluate(nlp.final_x(), &r, &J, nullptr, options.num_threads);
      }
      if (known && nlp.best_cost() >= 0.5 * r.squaredNorm() - cost_rounding(nlp.final_x(), r, J)) {
        end.x = nlp.final_x();
        end.cost = 0.5 * r.squaredNorm();
        end.r = r;
        end.J = J;
        end.known = true;
        return end;
      }
    }
    end.known = nlp.jacobian_at(end.x, end.r, end.J);
    return end;
  }

  std::string hessian(const SolverOptions& options) const {
    return settings_for<IpoptSettings>(name(), options).hessian;
  }
  std::string mu_strategy(const SolverOptions& options) const {
    return settings_for<IpoptSettings>(name(), options).mu_strategy;
  }
  // Debian's Ipopt has MUMPS built in; the HSL and Pardiso solvers load at run time when
  // present, and check_options rejects them when they cannot.
  std::string linear_solver(const SolverOptions& options) const {
    return settings_for<IpoptSettings>(name(), options).linear_solver;
  }

  static std::pair<TerminationType, std::string> termination(Ipopt::ApplicationReturnStatus status,
                                                             bool stopped_by_callback) {
    using T = TerminationType;
    const std::string what = std::string("Ipopt ") + status_name(status);
    switch (status) {
      case Ipopt::Solve_Succeeded:
        return {T::kConverged, std::string(detail::kGradientTestMessage) + " (" + what +
                                   ": optimality error below tol, max|J^T r| for an unbounded "
                                   "problem, and tol is 1e-300)"};
      case Ipopt::Solved_To_Acceptable_Level:
        return {T::kConverged, "relative cost change below tolerance (" + what +
                                   ": acceptable_tol held for acceptable_iter iterations and "
                                   "the cost stalled)"};
      case Ipopt::Maximum_Iterations_Exceeded:
        return {T::kMaxIterations, "reached max_iterations (" + what + ")"};
      case Ipopt::Maximum_CpuTime_Exceeded:
        return {T::kMaxIterations, what};
      case Ipopt::Diverging_Iterates:
        return {T::kDiverged, what};
      case Ipopt::User_Requested_Stop:
        if (stopped_by_callback) return {T::kUserStopped, "stopped by the callback"};
        return {T::kFailed, what};
      case Ipopt::Invalid_Option:
        return {T::kFailed, what +
                                " (Ipopt refused an option value, e.g. a linear solver it "
                                "cannot load)"};
      default:
        return {T::kFailed, what};
    }
  }
};

}  // namespace

const std::vector<SettingField<IpoptSettings>>& IpoptSettings::fields() {
  using S = IpoptSettings;
  static const std::vector<SettingField<S>> fields = {
      {"hessian", &S::hessian, {"gauss-newton", "limited-memory"}},
      {"mu_strategy", &S::mu_strategy, {"monotone", "adaptive"}},
      {"linear_solver",
       &S::linear_solver,
       {"mumps", "ma27", "ma57", "ma77", "ma86", "ma97", "pardiso"}}};
  return fields;
}

std::unique_ptr<Solver> make_ipopt_solver() { return std::make_unique<IpoptSolver>(); }

}  // namespace kincal
