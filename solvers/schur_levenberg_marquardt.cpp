#include "kincal/solvers/schur_levenberg_marquardt.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <thread>

#include "kincal/framework/base/small_lu.hpp"
#include "kincal/framework/calibration/implicit_configuration.hpp"
#include "kincal/solvers/solver_common.hpp"

namespace kincal {
namespace {

// Below this many configurations per thread a thread costs more than it saves.
constexpr int kMinConfigurationsPerThread = 256;
// As lm's (levenberg_marquardt.cpp): Ceres' trust-region defaults and Nielsen's updates; the
// initial radius and the growth cap come with the call (ImplicitTrustRegion).
constexpr double kMaxTrustRadius = 1e16;
constexpr double kMinTrustRadius = 1e-32;
constexpr double kMinRelativeDecrease = 1e-3;
constexpr int kMaxInvalidSteps = 10;
// How closely a trial point's poses are closed, as a multiple of the forward kinematics'
// tolerance (1e-10 in the constraints' unit by default). What is left over enters the reduced
// residuals through e - M g (first order), so the cost sees only its square: 1e-8 leaves
// ~1e-16, below the rounding of the readings.
constexpr double kClosureToleranceFactor = 100;

// The linearisation of every configuration at one point (parameters, poses), reduced onto
// the parameters. Per configuration j (k readings, rows j k .. j k + k - 1; Dof constraints,
// rows j Dof .. j Dof + Dof - 1):
//   M_j = H_pose G_pose^-1           how the readings see a move of the constraints,
//   E_j = H_params - M_j G_params    the readings' sensitivity with the closure held (the
//                                    nested problem's Jacobian rows),
//   C_j = I + M_j M_j^T / w^2 = L_j L_j^T,
// and the Schur complement of the pose block, in a form free of the w^2 terms that cancel in
// A - B D^-1 B^T: reduced rows R_j = L_j^-1 E_j and residuals rhat_j = L_j^-1 (e_j - M_j g_j).
// What the back-substitution needs is kept too: g_j, G_pose^-1 and G_params (free columns).
struct Linearization {
  std::vector<Pose> poses;
  MatrixXd R;        // m k x p
  VectorXd rhat;     // m k
  VectorXd errors;   // m k, whitened reading errors e_j
  MatrixXd M;        // m k x Dof (dynamic columns: one type for every Dof)
  MatrixXd L;        // m k x k
  VectorXd g;        // m Dof
  MatrixXd G_inv;    // m Dof x Dof
  MatrixXd G_theta;  // m Dof x p
  VectorXd costs;    // m, 1/2 |rhat_j|^2 per configuration
  double cost = 0;   // 1/2 |rhat|^2

  void resize(int m, int k, int p, int dof) {
    poses.resize(static_cast<std::size_t>(m));
    costs.setZero(m);
    R.setZero(m * k, p);
    rhat.setZero(m * k);
    errors.setZero(m * k);
    M.setZero(m * k, dof);
    L.setZero(m * k, k);
    g.setZero(m * dof);
    G_inv.setZero(m * dof, dof);
    G_theta.setZero(m * dof, p);
  }
  void swap(Linearization& other) {
    poses.swap(other.poses);
    R.swap(other.R);
    rhat.swap(other.rhat);
    errors.swap(other.errors);
    M.swap(other.M);
    L.swap(other.L);
    g.swap(other.g);
    G_inv.swap(other.G_inv);
    G_theta.swap(other.G_theta);
    costs.swap(other.costs);
    std::swap(cost, other.cost);
  }
};

template <int Dof>
class SchurKernel {
 public:
  using Vec = Eigen::Matrix<double, Dof, 1>;
  using Mat = Eigen::Matrix<double, Dof, Dof>;

  explicit SchurKernel(const ImplicitCalibrationProblem& problem)
      : problem_(problem),
        nested_(problem.nested()),
        model_(nested_.model()),
        mechanism_(*problem.template chain<Dof>()),
        m_(nested_.num_residual_blocks()),
        k_(model_.num_readings()),
        p_(nested_.num_parameters()),
        n_mech_(mechanism_.num_parameters()),
        w_(problem.weight()) {
    for (int f = 0; f < p_; ++f) {
      const int index = nested_.free_indices()[static_cast<std::size_t>(f)];
      if (index < n_mech_) free_mech_.emplace_back(f, index);
    }
  }

  int m() const { return m_; }
  int k() const { return k_; }
  int p() const { return p_; }

  // Configuration j's reduced rows at (`full`, `pose`) into `lin`, with `cost` = 1/2
  // |rhat_j|^2: the implicit cost of j minimised over its pose in the Gauss-Newton model. At a
  // closed pose that is the nested cost, and it stays free of the closure's rounding noise
  // (w^2 |g|^2 with w ~ 1e5 would add ~1e-8 of it). With `restore`, the pose is first moved
  // by Newton steps on the closure until it holds to the forward kinematics' tolerance (a
  // second-order correction of the linear step's poses). Without `rows`, the residuals only,
  // through the M and L of `rows_from` (the linearisation a step away: the first-order
  // correction e - M g is then good to second order in the closure error).
  bool linearize(int j, const VectorXd& full, Pose pose, bool restore, bool rows,
                 const Linearization& rows_from, Linearization& lin, double* cost,
                 std::string* why) const {
    thread_local ImplicitConfiguration<Dof> c;
    thread_local typename ClosedChainMechanism<Dof>::ParamsJacobian G_params;
    thread_local MatrixXd C;
    std::optional<SmallLu<Dof>> lu;
    thread_local Eigen::LLT<MatrixXd> llt;
    const auto q = nested_.data().actuators.row(j).transpose();
    const auto mech = full.head(n_mech_);
    const int row = j * k_, crow = j * Dof;
    *cost = 0;
    lin.poses[static_cast<std::size_t>(j)] = pose;
    if (!problem_.measured(j)) return true;  // rows stay zero
    auto fail = [&](const std::string& reason) {
      if (why) *why = "configuration " + std::to_string(j + 1) + ": " + reason;
      return false;
    };
    bool constraints_known = false;
    if (restore) {
      // Newton on the closure until it holds to kClosureToleranceFactor times the forward
      // kinematics' tolerance, starting with a chord step that uses rows_from's G_pose^-1
      // (factored at the pose the linear step started from): a matrix-vector product instead
      // of a factorisation, kept only if it lowers the residual, as it does unless the step
      // was long. The closure left over (after a chord step from a linear step of size d,
      // about d^3) is not rounded away: the constraints are evaluated where the pose ends, and
      // the reduced residual e - M g below corrects the readings for it to first order, so
      // what remains of it in the cost is of order g^2. That costs two evaluations of the
      // constraints and one factorisation per configuration when the chord step closes it,
      // one and one when the linear step did (docs/benchmarks.md).
      const ForwardKinematicsOptions& fk = model_.forward_kinematics_options();
      const double tolerance = kClosureToleranceFactor * fk.tolerance;
      mechanism_.constraints(mech, q, pose, c.g, &c.G_pose);
      double residual = c.g.cwiseAbs().maxCoeff();
      if (!std::isfinite(residual)) return fail("closure constraints not finite");
      if (residual > tolerance) {
        const Mat inverse = rows_from.G_inv.middleRows<Dof>(crow);
        const Pose chord = moved_pose<Dof>(mechanism_, pose, -(inverse * c.g));
        Vec g_chord;
        Mat G_chord;
        mechanism_.constraints(mech, q, chord, g_chord, &G_chord);
        const double residual_chord = g_chord.cwiseAbs().maxCoeff();
        if (residual_chord < residual) {
          pose = chord;
          c.g = g_chord;
          c.G_pose = G_chord;
          residual = residual_chord;
        }
      }
      for (int it = 0; residual > tolerance; ++it) {
        if (it >= fk.max_iterations)
          return fail("closure not restored (residual " + std::to_string(residual) + ")");
        lu.emplace(c.G_pose);
        if (lu->near_singular(c.G_pose)) return fail("closure Jacobian singular");
        pose = moved_pose<Dof>(mechanism_, pose, -lu->solve(c.g));
        mechanism_.constraints(mech, q, pose, c.g, &c.G_pose);
        residual = c.g.cwiseAbs().maxCoeff();
        if (!std::isfinite(residual)) return fail("closure constraints not finite");
      }
      lin.poses[static_cast<std::size_t>(j)] = pose;
      constraints_known = true;
    }
    std::string reason;
    if (!evaluate_implicit_configuration(model_, mechanism_, full, q,
                                         nested_.data().readings.row(j).transpose(), pose, rows, c,
                                         why ? &reason : nullptr, constraints_known))
      return fail(reason);
    lin.g.segment<Dof>(crow) = c.g;
    if (!rows) {
      for (int i = 0; i < k_; ++i) {
        double value = c.errors[i] - rows_from.M.row(row + i).dot(c.g.transpose());
        for (int l = 0; l < i; ++l) value -= rows_from.L(row + i, l) * lin.rhat[row + l];
        lin.rhat[row + i] = value / rows_from.L(row + i, i);
      }
      *cost = 0.5 * lin.rhat.segment(row, k_).squaredNorm();
      return std::isfinite(*cost);
    }
    lu.emplace(c.G_pose);
    if (lu->near_singular(c.G_pose)) return fail("closure Jacobian singular");
    lin.G_inv.middleRows<Dof>(crow) = lu->inverse();
    G_params.resize(Dof, n_mech_);
    mechanism_.constraint_jacobian_params(mech, q, pose, G_params);
    auto G_theta = lin.G_theta.middleRows<Dof>(crow);
    for (const auto& [f, index] : free_mech_) G_theta.col(f) = G_params.col(index);
    for (int i = 0; i < k_; ++i) {
      const Vec lambda = lu->solve_transposed(c.H_pose.row(i).transpose());  // M row i
      lin.M.row(row + i) = lambda.transpose();
      lin.errors[row + i] = c.errors[i];
      lin.rhat[row + i] = c.errors[i] - lambda.dot(c.g);
      // Column by column with fixed-size dot products: G_theta's columns are contiguous,
      // R's rows are not (a dynamic row product here was a tenth of the solve).
      auto R_row = lin.R.row(row + i);
      for (int f = 0; f < p_; ++f)
        R_row[f] = c.H_params(i, nested_.free_indices()[static_cast<std::size_t>(f)]) -
                   lambda.dot(G_theta.col(f).template head<Dof>());
    }
    // C = I + M M^T / w^2 = L L^T; rows and residuals whitened by L^-1.
    const auto Mj = lin.M.middleRows(row, k_);
    if (k_ == 1) {
      const double l = std::sqrt(1.0 + Mj.row(0).squaredNorm() / (w_ * w_));
      lin.L(row, 0) = l;
      lin.R.row(row) /= l;
      lin.rhat[row] /= l;
    } else {
      C.noalias() = Mj * Mj.transpose() / (w_ * w_);
      C.diagonal().array() += 1.0;
      llt.compute(C);
      lin.L.middleRows(row, k_) = llt.matrixL();
      llt.matrixL().solveInPlace(lin.R.middleRows(row, k_));
      llt.matrixL().solveInPlace(lin.rhat.segment(row, k_));
    }
    *cost = 0.5 * lin.rhat.segment(row, k_).squaredNorm();
    return std::isfinite(*cost);
  }

  // The pose step of configuration j for the parameter step dx, from the linearisation
  // `lin`: the u = G_pose dp minimising w^2 |g + G_params dx + u|^2 + |e + H_params dx + M u|^2
  // (the Schur complement's back-substitution), in the same w^2-free form, with
  // H_params dx = E dx + M G_params dx and E dx = L (R dx). `R_dx` = lin.R dx and `G_dx` =
  // lin.G_theta dx, formed for every configuration at once (pose_products): two
  // matrix-vector products over contiguous columns instead of strided rows per configuration.
  Vec pose_step(int j, const VectorXd& R_dx, const VectorXd& G_dx_all,
                const Linearization& lin) const {
    if (!problem_.measured(j)) return Vec::Zero();
    const int row = j * k_, crow = j * Dof;
    const Vec G_dx = G_dx_all.segment<Dof>(crow);
    const Vec a = lin.g.segment<Dof>(crow) + G_dx;
    Vec u;
    if (k_ == 1) {
      // (w^2 I + m m^T)^-1 m = m / (w^2 + |m|^2): no factorisation.
      const Vec mi = lin.M.row(row).transpose();
      const double d = lin.errors[row] + lin.L(row, 0) * R_dx[row] + mi.dot(G_dx);
      u = -a - mi * ((d - mi.dot(a)) / (w_ * w_ + mi.squaredNorm()));
    } else {
      Vec rhs = Vec::Zero();
      Mat normal = Mat::Identity() * (w_ * w_);
      for (int i = 0; i < k_; ++i) {
        double reduced = 0;
        for (int l = 0; l <= i; ++l) reduced += lin.L(row + i, l) * R_dx[row + l];
        const Vec mi = lin.M.row(row + i).transpose();
        const double d = lin.errors[row + i] + reduced + mi.dot(G_dx);
        rhs += mi * (d - mi.dot(a));
        normal += mi * mi.transpose();
      }
      u = -a - normal.llt().solve(rhs);
    }
    return lin.G_inv.middleRows<Dof>(crow) * u;
  }

  // R_dx and G_dx of pose_step for the parameter step dx (sized once by the caller).
  static void pose_products(const Linearization& lin, const VectorXd& dx, VectorXd& R_dx,
                            VectorXd& G_dx) {
    R_dx.noalias() = lin.R * dx;
    G_dx.noalias() = lin.G_theta * dx;
  }

  // Linearises every configuration at (`full`, `poses`), restoring the closure first when
  // `restore`. Threads over configurations when there are many; the cost is summed in
  // configuration order whatever the threads, so the result does not depend on their number.
  bool linearize_all(const VectorXd& full, const std::vector<Pose>& poses, bool restore, bool rows,
                     const Linearization& rows_from, Linearization& lin, int num_threads,
                     std::string* why) const {
    auto run = [&](int begin, int end, std::string* reason) {
      for (int j = begin; j < end; ++j)
        if (!linearize(j, full, poses[static_cast<std::size_t>(j)], restore, rows, rows_from, lin,
                       &lin.costs[j], reason))
          return false;
      return true;
    };
    const int threads = std::max(1, std::min(num_threads, m_ / kMinConfigurationsPerThread));
    bool ok = true;
    if (threads <= 1) {
      ok = run(0, m_, why);
    } else {
      std::vector<std::thread> pool;
      std::vector<std::string> reasons(static_cast<std::size_t>(threads));
      std::vector<char> done(static_cast<std::size_t>(threads), 1);
      const int chunk = (m_ + threads - 1) / threads;
      for (int t = 0; t < threads; ++t) {
        const int begin = t * chunk, end = std::min(m_, begin + chunk);
        pool.emplace_back([&, t, begin, end] {
          const auto s = static_cast<std::size_t>(t);
          done[s] = run(begin, end, &reasons[s]);
        });
      }
      for (auto& th : pool) th.join();
      for (int t = 0; t < threads && ok; ++t) {
        const auto s = static_cast<std::size_t>(t);
        if (!done[s]) {
          if (why) *why = reasons[s];
          ok = false;
        }
      }
    }
    if (!ok) return false;
    lin.cost = lin.costs.sum();
    return true;
  }

  Pose moved(const Pose& pose, const Vec& step) const {
    return moved_pose<Dof>(mechanism_, pose, step);
  }

 private:
  const ImplicitCalibrationProblem& problem_;
  const CalibrationProblem& nested_;
  const MeasurementModel& model_;
  const ClosedChainMechanism<Dof>& mechanism_;
  int m_, k_, p_, n_mech_;
  double w_;
  std::vector<std::pair<int, int>> free_mech_;  // (free column, mechanism parameter)
};

template <int Dof>
Summary solve_with(const ImplicitCalibrationProblem& problem, VectorXd& x,
                   const SolverOptions& options, const ImplicitTrustRegion& trust_region) {
  const SchurKernel<Dof> kernel(problem);
  const CalibrationProblem& nested = problem.nested();
  const int m = kernel.m(), k = kernel.k(), n = kernel.p();
  Summary summary;
  summary.solver = "lm";
  detail::SolveMonitor monitor(options, summary);
  summary.trace.reserve(static_cast<std::size_t>(std::min(options.max_iterations, 10000)) + 1);

  Linearization lin, trial;
  lin.resize(m, k, n, Dof);
  trial.resize(m, k, n, Dof);
  std::vector<Pose> poses(static_cast<std::size_t>(m));
  for (int j = 0; j < m; ++j) poses[static_cast<std::size_t>(j)] = problem.reference_pose(j);
  MatrixXd S(n, n), H(n, n);
  Eigen::LLT<MatrixXd> llt(n);
  VectorXd gradient(n), column_scale = VectorXd::Zero(n), velocity(n), acceleration(n), y(n), dx(n),
                        dx_velocity(n), x_trial(n), probe_step(n), model_r(m * k), second(m * k);
  StationarityScratch scratch(m * k, n);
  Stationarity at_x;

  // The full parameter vector of a point: the fixed entries never change, so only the free
  // ones are written (full_parameters() would allocate a new vector at every trial).
  VectorXd full = nested.full_parameters(x);
  const auto& free = nested.free_indices();
  auto full_at = [&](const VectorXd& at) -> const VectorXd& {
    for (std::size_t i = 0; i < free.size(); ++i) full[free[i]] = at[static_cast<Eigen::Index>(i)];
    return full;
  };
  std::string why;
  ++summary.residual_evaluations;
  ++summary.jacobian_evaluations;
  if (!problem.start_failure().empty() ||
      !kernel.linearize_all(full_at(x), poses, false, true, lin, lin, options.num_threads, &why)) {
    summary.initial_cost = summary.final_cost = std::numeric_limits<double>::infinity();
    monitor.finish(TerminationType::kFailed,
                   "residuals not computable at the start: " +
                       (problem.start_failure().empty() ? why : problem.start_failure()));
    return summary;
  }
  {
    const std::string non_finite =
        detail::non_finite_start(lin.rhat, &lin.R, nested.parameter_names());
    if (!non_finite.empty() || !std::isfinite(lin.cost)) {
      summary.initial_cost = summary.final_cost = std::numeric_limits<double>::infinity();
      monitor.finish(TerminationType::kFailed,
                     (non_finite.empty() ? "the cost at the start is not finite" : non_finite) +
                         " (implicit formulation)");
      return summary;
    }
  }
  summary.initial_cost = summary.final_cost = lin.cost;

  // Scaled normal equations of the reduced problem at the current iterate: the Schur
  // complement S = R^T R, in the variables y = D^(1/2) dx of lm's Marquardt scaling.
  // Returns max|g| (for the trace) and sets relative_gradient, the gradient test's measure
  // before rounding (stationarity.hpp), which a common scale of the residuals does not change.
  double relative_gradient = 0;
  auto prepare = [&] {
    gradient.noalias() = lin.R.transpose() * lin.rhat;
    const double residual_norm = lin.rhat.norm();
    relative_gradient = 0;
    for (int c = 0; c < n; ++c) {
      const double column = lin.R.col(c).norm();
      column_scale[c] = std::max(column_scale[c], column);
      if (!dead_column(column, x[c], residual_norm))
        relative_gradient = std::max(
            relative_gradient, relative_gradient_entry(gradient[c], column, residual_norm, x[c]));
    }
    const double largest = n ? column_scale.maxCoeff() : 0.0;
    const double floor = largest > 0 ? 1e-12 * largest : 1.0;
    column_scale = column_scale.cwiseMax(floor);
    S.setZero();
    S.selfadjointView<Eigen::Lower>().rankUpdate(lin.R.transpose());
    // Mirror and scale entry by entry: expressions with S on both sides would need a temporary.
    for (int c = 0; c < n; ++c)
      for (int r = 0; r < n; ++r) {
        if (r < c) S(r, c) = S(c, r);
        H(r, c) = S(r, c) / (column_scale[r] * column_scale[c]);
      }
    return n == 0 ? 0.0 : gradient.lpNorm<Eigen::Infinity>();
  };
  // out = -(H + lambda I)^-1 D^-1/2 R^T z with the current factorisation.
  auto damped_solve = [&](const VectorXd& z, VectorXd& out) {
    out.noalias() = lin.R.transpose() * z;
    out = -(column_scale.cwiseInverse().asDiagonal() * out);
    llt.solveInPlace(out);
    return out.allFinite();
  };
  // The poses moved by the back-substituted steps for the parameter step `step`.
  VectorXd R_step(m * k), G_step(m * Dof);
  auto move_poses = [&](const VectorXd& step) {
    SchurKernel<Dof>::pose_products(lin, step, R_step, G_step);
    for (int j = 0; j < m; ++j) {
      const auto s = static_cast<std::size_t>(j);
      poses[s] = kernel.moved(lin.poses[s], kernel.pose_step(j, R_step, G_step, lin));
    }
  };
  auto test_holds = [&](bool gradient_claim) {
    measure_stationarity(x, lin.rhat, lin.R, options, scratch, at_x);
    return at_x.on_plateau() || at_x.claim_holds(options, gradient_claim);
  };
  // The verdict is the nested problem's, at the x returned, its forward kinematics started
  // from x's closed poses (lin's; a cold start from home took 7 % of a case-5 solve).
  auto done = [&](TerminationType type, std::string message) {
    VectorXd r;
    MatrixXd J;
    ++summary.residual_evaluations;
    ++summary.jacobian_evaluations;
    const std::unique_ptr<WarmStart> closed = nested.make_warm_start(lin.poses);
    if (!nested.evaluate(x, &r, &J, &why, options.num_threads, closed.get())) {
      summary.final_cost = std::numeric_limits<double>::infinity();
      monitor.finish(TerminationType::kFailed,
                     "the nested problem cannot be evaluated at the implicit solution: " + why);
      return summary;
    }
    summary.final_cost = 0.5 * r.squaredNorm();
    if (type == TerminationType::kConverged) {
      measure_stationarity(x, r, J, options, scratch, at_x);
      const detail::Verdict verdict =
          detail::judge_convergence(at_x, options, message, nested.parameter_names());
      type = verdict.type;
      message = verdict.message;
    }
    monitor.finish(type, std::move(message) + " (implicit formulation)");
    return summary;
  };

  double cost = lin.cost;
  double gradient_norm = prepare();
  // lm's check that the undamped (Gauss-Newton) model, not only the damped step, promises no
  // more than function_tolerance (stationarity.hpp's cost test), on the p x p Schur
  // complement instead of a QR of the reduced rows: 1/2 g^T S^-1 g.
  Eigen::LDLT<MatrixXd> ldlt(n);
  VectorXd gn_step(n);
  auto gauss_newton_settled = [&] {
    ldlt.compute(S);
    gn_step = ldlt.solve(gradient);
    const double decrease = 0.5 * gradient.dot(gn_step);
    return gn_step.allFinite() &&
           decrease <= options.function_tolerance * cost + cost_rounding(x, lin.rhat, lin.R);
  };
  double radius = trust_region.initial_radius, decrease_factor = 2;
  if (!monitor.record({0, cost, gradient_norm, 0, 1.0 / radius, 0}, x))
    return done(TerminationType::kUserStopped, "stopped by the callback");
  auto reject = [&] {
    radius /= decrease_factor;
    decrease_factor *= 2;
  };
  int consecutive_invalid = 0;
  for (int iteration = 1;; ++iteration) {
    if (relative_gradient <= options.gradient_tolerance && test_holds(true))
      return done(TerminationType::kConverged, detail::kGradientTestMessage);
    if (radius < kMinTrustRadius)
      return done(TerminationType::kConverged, "trust region radius below min_trust_radius");
    if (iteration > options.max_iterations)
      return done(TerminationType::kMaxIterations, "reached max_iterations");
    summary.iterations = iteration;

    const double lambda = 1.0 / radius;
    H.diagonal().array() += lambda;
    llt.compute(H);
    H.diagonal().array() -= lambda;
    if (llt.info() != Eigen::Success || !damped_solve(lin.rhat, velocity)) {
      if (++consecutive_invalid > kMaxInvalidSteps)
        return done(TerminationType::kDiverged, "damped normal equations could not be solved");
      reject();
      continue;
    }
    dx_velocity.noalias() = column_scale.cwiseInverse().asDiagonal() * velocity;
    model_r.noalias() = lin.R * dx_velocity;
    model_r += lin.rhat;
    // The reduced model: the joint one with every pose at its optimum for dx.
    const double predicted = cost - 0.5 * model_r.squaredNorm();
    if (lambda <= 1.0 && consecutive_invalid == 0 &&
        predicted <= options.function_tolerance * cost && gauss_newton_settled()) {
      // Ceres' relative cost test on the model (as lm): take this last step if it does not
      // raise the cost, and stop.
      x_trial = x + dx_velocity;
      move_poses(dx_velocity);
      ++summary.residual_evaluations;
      if (kernel.linearize_all(full_at(x_trial), poses, true, false, lin, trial,
                               options.num_threads, nullptr) &&
          trial.cost < cost) {
        x.swap(x_trial);
        lin.poses.swap(trial.poses);  // x's poses, for done()
        if (!monitor.record(
                {iteration, trial.cost, gradient_norm, dx_velocity.norm(), 1.0 / radius, 0}, x))
          return done(TerminationType::kUserStopped, "stopped by the callback");
      }
      return done(TerminationType::kConverged, "predicted relative cost decrease below tolerance");
    }
    // Geodesic acceleration (as lm): the second directional derivative of the reduced
    // residuals along v, from one residual evaluation at x + h v with the poses moved by h
    // times their steps and closed again.
    y = velocity;
    bool accelerated = false;
    {
      constexpr double h = 0.1, max_acceleration = 0.75;
      x_trial = x + h * dx_velocity;
      probe_step = h * dx_velocity;
      move_poses(probe_step);
      ++summary.residual_evaluations;
      if (kernel.linearize_all(full_at(x_trial), poses, false, false, lin, trial,
                               options.num_threads, nullptr)) {
        second.noalias() = lin.R * dx_velocity;
        second = (2.0 / h) * ((trial.rhat - lin.rhat) / h - second);
        if (damped_solve(second, acceleration) &&
            2.0 * acceleration.norm() <= max_acceleration * velocity.norm()) {
          y += 0.5 * acceleration;
          accelerated = true;
        }
      }
    }
    dx.noalias() = column_scale.cwiseInverse().asDiagonal() * y;
    x_trial = x + dx;
    if (consecutive_invalid == 0 && detail::small_step(dx, x, options.parameter_tolerance) &&
        test_holds(false))
      return done(TerminationType::kConverged, "relative step below tolerance");

    // Back-substitution: each pose moves by its step, then the closure is restored there.
    move_poses(dx);
    ++summary.residual_evaluations;
    ++summary.jacobian_evaluations;
    const bool evaluated = kernel.linearize_all(full_at(x_trial), poses, true, true, lin, trial,
                                                options.num_threads, &why);
    if (!evaluated || !std::isfinite(trial.cost) || !trial.R.allFinite()) {
      if (++consecutive_invalid > kMaxInvalidSteps)
        return done(TerminationType::kDiverged,
                    std::to_string(consecutive_invalid) +
                        " consecutive trial points where residuals could not be computed" +
                        (evaluated ? std::string() : "; last: " + why));
      reject();
      continue;
    }
    consecutive_invalid = 0;
    // With acceleration the prediction is that of the velocity alone (as lm).
    double model_decrease = predicted;
    if (!accelerated) {
      model_r.noalias() = lin.R * dx;
      model_r += lin.rhat;
      model_decrease = cost - 0.5 * model_r.squaredNorm();
    }
    const double actual = cost - trial.cost;
    const double rho = model_decrease > 0 ? actual / model_decrease : -1.0;
    const bool cost_flat = detail::small_cost_change(cost, trial.cost, options.function_tolerance);
    if (actual > 0 && rho > kMinRelativeDecrease) {
      x.swap(x_trial);
      lin.swap(trial);
      cost = lin.cost;
      radius = std::min(kMaxTrustRadius, radius / std::max(1.0 / trust_region.max_growth,
                                                           1.0 - std::pow(2.0 * rho - 1.0, 3)));
      decrease_factor = 2;
      gradient_norm = prepare();
      if (!monitor.record({iteration, cost, gradient_norm, dx.norm(), 1.0 / radius, 0}, x))
        return done(TerminationType::kUserStopped, "stopped by the callback");
    } else {
      reject();
    }
    if (cost_flat && test_holds(false))
      return done(TerminationType::kConverged, "relative cost change below tolerance");
  }
}

template <int Dof>
VectorXd schur_step_with(const ImplicitCalibrationProblem& problem, const VectorXd& x_joint,
                         const VectorXd& damping) {
  const SchurKernel<Dof> kernel(problem);
  const CalibrationProblem& nested = problem.nested();
  const int m = kernel.m(), n = kernel.p();
  Linearization lin;
  lin.resize(m, kernel.k(), n, Dof);
  std::vector<Pose> poses(static_cast<std::size_t>(m));
  for (int j = 0; j < m; ++j) poses[static_cast<std::size_t>(j)] = problem.reference_pose(j);
  const VectorXd x = x_joint.head(n);
  std::string why;
  if (!kernel.linearize_all(nested.full_parameters(x), poses, false, true, lin, lin, 1, &why))
    throw std::runtime_error("implicit_schur_step: " + why);
  MatrixXd S = lin.R.transpose() * lin.R;
  S.diagonal() += damping;
  const VectorXd dx = -S.llt().solve(lin.R.transpose() * lin.rhat);
  VectorXd step(problem.num_parameters());
  step.head(n) = dx;
  VectorXd R_dx(m * kernel.k()), G_dx(m * Dof);
  SchurKernel<Dof>::pose_products(lin, dx, R_dx, G_dx);
  for (int j = 0; j < m; ++j) step.segment<Dof>(n + Dof * j) = kernel.pose_step(j, R_dx, G_dx, lin);
  return step;
}

}  // namespace

Summary solve_implicit_lm(const ImplicitCalibrationProblem& problem, VectorXd& x,
                          const SolverOptions& options, const ImplicitTrustRegion& trust_region) {
  if (x.size() != problem.num_free_parameters())
    throw InvalidSolverOptions("lm: x has " + std::to_string(x.size()) + " entries, the problem " +
                               std::to_string(problem.num_free_parameters()) + " free parameters");
  return problem.dof() == 6 ? solve_with<6>(problem, x, options, trust_region)
                            : solve_with<3>(problem, x, options, trust_region);
}

VectorXd implicit_schur_step(const ImplicitCalibrationProblem& problem, const VectorXd& x_joint,
                             const VectorXd& damping) {
  return problem.dof() == 6 ? schur_step_with<6>(problem, x_joint, damping)
                            : schur_step_with<3>(problem, x_joint, damping);
}

}  // namespace kincal
