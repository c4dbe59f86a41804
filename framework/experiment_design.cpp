#include "kincal/framework/experiment_design.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "kincal/framework/random.hpp"

namespace kincal {

namespace {

// Asks options.monitor whether to go on (always, without one).
bool keep_going(const DesignOptions& options, const char* stage, long done, long total,
                int pass = 0) {
  if (!options.monitor) return true;
  DesignStep step;
  step.stage = stage;
  step.done = done;
  step.total = total;
  step.pass = pass;
  return options.monitor(step);
}

}  // namespace

const char* to_string(DesignCriterion criterion) {
  switch (criterion) {
    case DesignCriterion::kD:
      return "D";
    case DesignCriterion::kA:
      return "A";
    case DesignCriterion::kE:
      return "E";
    case DesignCriterion::kI:
      return "I";
  }
  return "?";
}

DesignCriterion parse_design_criterion(const std::string& text) {
  if (text == "D" || text == "d") return DesignCriterion::kD;
  if (text == "A" || text == "a") return DesignCriterion::kA;
  if (text == "E" || text == "e") return DesignCriterion::kE;
  if (text == "I" || text == "i") return DesignCriterion::kI;
  throw std::invalid_argument("unknown design criterion '" + text + "' (expected D, A, E or I)");
}

// ---------------------------------------------------------------------------------------
// Singularity margin

SingularityGauge::SingularityGauge(const MeasurementModel& model, const VectorXd& params)
    : model_(model), params_(params) {
  const Mechanism& mechanism = model.mechanism();
  home_.resize(mechanism.num_actuators());
  const InverseKinematicsResult ik =
      mechanism.home_actuators(params.head(mechanism.num_parameters()), home_);
  if (!ik.ok())
    throw std::invalid_argument("the model's home pose is not reachable: inverse kinematics " +
                                ik.describe());
  const ForwardKinematicsResult fk =
      mechanism.forward_kinematics(params.head(mechanism.num_parameters()), home_,
                                   mechanism.home_pose(), model.forward_kinematics_options());
  if (!fk.ok())
    throw std::invalid_argument("forward kinematics at the model's home configuration " +
                                fk.describe());
  Matrix6Xd J;
  // No moving actuator (every range 0) has no Jacobian to weigh: a block of a 6 x 0 matrix is
  // undefined behaviour in Eigen.
  if (actuator_jacobian(home_, fk.pose, J) && J.cols() > 0) {
    const double t = J.topRows<3>().norm(), r = J.bottomRows<3>().norm();
    rotation_length_ = r > 0 && t > 0 ? t / r : 1;
  }
  home_inverse_condition_ = inverse_condition(home_, fk.pose);
  if (!(home_inverse_condition_ > 0)) home_inverse_condition_ = 1;
}

bool SingularityGauge::actuator_jacobian(const ActuatorsRef& q, const Pose& pose,
                                         Matrix6Xd& J) const {
  const Mechanism& mechanism = model_.mechanism();
  const VectorXd& range = model_.actuator_ranges();
  const int na = mechanism.num_actuators();
  Matrix6Xd all(6, na);
  if (!mechanism.pose_jacobian_actuators(params_.head(mechanism.num_parameters()), q, pose,
                                         model_.forward_kinematics_options(), all))
    return false;
  int moving = 0;
  for (int i = 0; i < na; ++i) moving += range[i] > 0;
  J.resize(6, moving);
  int column = 0;
  for (int i = 0; i < na; ++i)
    if (range[i] > 0) J.col(column++) = all.col(i) * range[i];  // a fixed actuator has no say
  return true;
}

double SingularityGauge::inverse_condition(const ActuatorsRef& q, const Pose& pose) const {
  Matrix6Xd J;
  if (!actuator_jacobian(q, pose, J)) return 0;
  if (J.cols() == 0) return 1;
  J.bottomRows<3>() *= rotation_length_;
  // The singular values of J are the square roots of the largest min(6, columns) eigenvalues
  // of the fixed-size J J^T: cheaper than an SVD of J, and precise enough for a margin (it
  // loses only conditions beyond 1e8).
  const Matrix6d JJt = J * J.transpose();
  const Vector6d l = Eigen::SelfAdjointEigenSolver<Matrix6d>(JJt, Eigen::EigenvaluesOnly)
                         .eigenvalues();  // ascending
  const int k = static_cast<int>(std::min<Eigen::Index>(6, J.cols()));
  return l[5] > 0 ? std::sqrt(std::max(l[6 - k], 0.0) / l[5]) : 0;
}

double SingularityGauge::margin(const ActuatorsRef& q, const Pose& pose) const {
  return inverse_condition(q, pose) / home_inverse_condition_;
}

// ---------------------------------------------------------------------------------------
// Setup and candidates

namespace {

enum Stream : std::uint64_t { kCandidateStream = 21, kWorkspaceStream = 22, kRandomStream = 23 };

// The normalised whitened rows of the readings of `sensor` from a full reading Jacobian.
void sensor_rows(const MeasurementModel& model, const DesignSetup& setup, const MatrixXd& J,
                 int sensor, Eigen::Ref<MatrixXd> out) {
  const int o = model.sensor_reading_offset(sensor);
  const int k = model.sensors()[sensor]->num_readings();
  for (int r = 0; r < k; ++r)
    for (std::size_t c = 0; c < setup.free_indices.size(); ++c)
      out(r, static_cast<int>(c)) = J(o + r, setup.free_indices[c]) *
                                    setup.scale[static_cast<int>(c)] / setup.noise_std[o + r];
}

}  // namespace

DesignSetup make_design_setup(const MeasurementModel& model, const DesignOptions& options,
                              const Measurements* existing) {
  DesignSetup s;
  s.free_indices = model.parameters().free_indices();
  const int n = static_cast<int>(s.free_indices.size());
  if (n == 0) throw std::invalid_argument("no free parameters: nothing to design for");
  s.scale = nominal_parameter_std(model, s.free_indices, options.default_error_mm,
                                  options.default_error_rad);
  s.noise_std = options.noise_std.size() ? options.noise_std : model.reading_std();
  if (s.noise_std.size() != model.num_readings() || !(s.noise_std.array() > 0).all() ||
      !s.noise_std.allFinite())
    throw std::invalid_argument("the reading noise std must be finite and > 0 for every reading");
  if (!(options.orientation_length >= 0) || !std::isfinite(options.orientation_length))
    throw std::invalid_argument("the orientation length must be finite and >= 0");
  s.base_information = MatrixXd::Zero(n, n);
  for (int c = 0; c < n; ++c) {
    const Parameter& p = model.parameters()[s.free_indices[c]];
    if (!p.has_prior()) continue;
    s.has_prior = true;
    s.base_information(c, c) += std::pow(s.scale[c] / p.prior_std, 2);
  }
  const VectorXd nominal = model.parameters().nominal_values();
  if (existing && existing->size() > 0) {
    auto ws = model.make_workspace();
    VectorXd readings(model.num_readings());
    MatrixXd J(model.num_readings(), model.num_parameters());
    Eigen::Ref<MatrixXd> J_ref(J);
    for (int row = 0; row < existing->size(); ++row) {
      const ForwardKinematicsResult fk =
          model.predict(nominal, existing->actuators.row(row).transpose(), readings, &J_ref, ws);
      if (!fk.ok())
        throw std::invalid_argument("existing data row " + std::to_string(row + 1) +
                                    ": forward kinematics at the nominal values " + fk.describe());
      for (int sensor = 0; sensor < static_cast<int>(model.sensors().size()); ++sensor) {
        const int o = model.sensor_reading_offset(sensor);
        if (std::isnan(existing->readings(row, o))) continue;
        MatrixXd x(model.sensors()[sensor]->num_readings(), n);
        sensor_rows(model, s, J, sensor, x);
        s.base_information += x.transpose() * x;
        s.existing_readings += static_cast<int>(x.rows());
      }
    }
  }
  s.workspace = sample_workspace(model, nominal, s.free_indices, options.workspace_samples,
                                 derive_seed(options.seed, kWorkspaceStream));
  s.workspace_weight = MatrixXd::Zero(n, n);
  const double l2 = options.orientation_length * options.orientation_length;
  for (const Matrix6Xd& J : s.workspace.J_free) {
    const MatrixXd Jp = J.topRows<3>() * s.scale.asDiagonal();
    s.workspace_weight += Jp.transpose() * Jp;
    if (l2 > 0) {
      const MatrixXd Jr = J.bottomRows<3>() * s.scale.asDiagonal();
      s.workspace_weight += l2 * (Jr.transpose() * Jr);
    }
  }
  if (!s.workspace.J_free.empty()) s.workspace_weight /= double(s.workspace.J_free.size());
  return s;
}

DesignCandidates make_design_candidates(const MeasurementModel& model, const DesignSetup& setup,
                                        const DesignOptions& options) {
  const Mechanism& mechanism = model.mechanism();
  const int na = mechanism.num_actuators();
  const int n = static_cast<int>(setup.free_indices.size());
  const VectorXd nominal = model.parameters().nominal_values();
  const SingularityGauge gauge(model, nominal);
  const VectorXd& home = gauge.home_actuators();
  const VectorXd& range = model.actuator_ranges();
  const int num_corners = na <= 12 ? (1 << na) : 0;
  const int total = num_corners + std::max(options.num_random, 0);

  DesignCandidates out;
  const int num_sensors = static_cast<int>(model.sensors().size());
  std::vector<int> k(num_sensors);
  int rows_per_configuration = 0;
  for (int s = 0; s < num_sensors; ++s)
    rows_per_configuration += k[s] = model.sensors()[s]->num_readings();
  out.configurations.resize(total, na);
  out.margins.resize(total);
  out.rows.resize(static_cast<Eigen::Index>(total) * rows_per_configuration, n);
  out.row_offset.push_back(0);
  auto ws = model.make_workspace();
  VectorXd readings(model.num_readings()), q(na);
  MatrixXd J(model.num_readings(), model.num_parameters());
  Eigen::Ref<MatrixXd> J_ref(J);
  Random rng(derive_seed(options.seed, kCandidateStream));
  int kept = 0;
  for (int i = 0; i < total; ++i) {
    if (i % 256 == 0 && !keep_going(options, "candidates", i, total)) {
      out.stopped = true;
      break;
    }
    const bool corner = i < num_corners;
    for (int a = 0; a < na; ++a)
      q[a] = home[a] + (corner ? ((i >> a) & 1 ? range[a] : -range[a]) : rng.symmetric(range[a]));
    const ForwardKinematicsResult fk = model.predict(nominal, q, readings, &J_ref, ws);
    if (!fk.ok() || !J.allFinite()) {
      ++out.rejected_unreachable;
      continue;
    }
    const double margin = gauge.margin(q, fk.pose);
    if (!(margin >= options.min_singularity_margin)) {
      ++out.rejected_singular;
      continue;
    }
    if (corner) ++out.num_corners;
    out.configurations.row(kept) = q.transpose();
    out.margins[kept] = margin;
    for (int s = 0; s < num_sensors; ++s) {
      const int first = out.row_offset.back();
      sensor_rows(model, setup, J, s, out.rows.middleRows(first, k[s]));
      out.configuration.push_back(kept);
      out.sensor.push_back(s);
      out.row_offset.push_back(first + k[s]);
    }
    ++kept;
  }
  out.configurations.conservativeResize(kept, na);
  out.margins.conservativeResize(kept);
  out.rows.conservativeResize(out.row_offset.back(), n);
  return out;
}

// ---------------------------------------------------------------------------------------
// Criteria

MatrixXd design_information(const DesignCandidates& candidates, const std::vector<int>& chosen,
                            const DesignSetup& setup) {
  MatrixXd M = setup.base_information;
  for (int c : chosen) {
    const auto X = candidates.rows.middleRows(
        candidates.row_offset[c], candidates.row_offset[c + 1] - candidates.row_offset[c]);
    M.noalias() += X.transpose() * X;
  }
  return M;
}

double criterion_value(DesignCriterion criterion, const MatrixXd& M, const DesignSetup& setup) {
  const int n = static_cast<int>(M.rows());
  const Eigen::SelfAdjointEigenSolver<MatrixXd> eig(M);
  const VectorXd& l = eig.eigenvalues();
  const double inf = std::numeric_limits<double>::infinity();
  if (criterion == DesignCriterion::kE) return l[0];
  if (criterion == DesignCriterion::kD) return l[0] > 0 ? l.array().log().sum() : -inf;
  if (!(l[0] > 1e-14 * std::max(l[n - 1], 1e-300))) return inf;
  const MatrixXd inverse =
      eig.eigenvectors() * l.cwiseInverse().asDiagonal() * eig.eigenvectors().transpose();
  if (criterion == DesignCriterion::kA) return inverse.trace() / n;
  return (setup.workspace_weight * inverse).trace();
}

MatrixXd design_covariance(const MatrixXd& M, const DesignSetup& setup) {
  const int n = static_cast<int>(M.rows());
  const Eigen::SelfAdjointEigenSolver<MatrixXd> eig(M);
  const VectorXd& l = eig.eigenvalues();
  if (!(l[0] > 1e-14 * std::max(l[n - 1], 1e-300)))
    return MatrixXd::Constant(n, n, std::numeric_limits<double>::quiet_NaN());
  const MatrixXd inverse =
      eig.eigenvectors() * l.cwiseInverse().asDiagonal() * eig.eigenvectors().transpose();
  return setup.scale.asDiagonal() * inverse * setup.scale.asDiagonal();
}

// ---------------------------------------------------------------------------------------
// The exchange

namespace {

constexpr int kMaxRows = 16;
using SmallMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxRows, kMaxRows>;

// M^-1 and, per candidate, G = X^T M^-1 X and (A, I) H = X^T M^-1 W M^-1 X kept up to date
// under rank-one changes of M.
class ExchangeState {
 public:
  ExchangeState(const DesignCandidates& candidates, const DesignSetup& setup,
                DesignCriterion criterion)
      : c_(candidates), criterion_(criterion), n_(static_cast<int>(candidates.rows.cols())) {
    linear_ = criterion == DesignCriterion::kA || criterion == DesignCriterion::kI;
    W_ = criterion == DesignCriterion::kI ? setup.workspace_weight
                                          : MatrixXd(MatrixXd::Identity(n_, n_) / n_);
    // A ridge far below any information a measurement or a prior adds keeps M invertible
    // while the greedy start has fewer readings than parameters.
    const double mean_row = c_.rows.rows() ? c_.rows.squaredNorm() / c_.rows.rows() : 1.0;
    M0_ = setup.base_information;
    M0_.diagonal().array() += 1e-9 * std::max(mean_row, 1e-300) + 1e-300;
    unit_rows_ = true;
    g_offset_.push_back(0);
    for (int c = 0; c < c_.size(); ++c) {
      const int k = rows(c);
      if (k > kMaxRows)
        throw std::invalid_argument("a sensor with more than 16 readings cannot be designed for");
      unit_rows_ = unit_rows_ && k == 1;
      g_offset_.push_back(g_offset_.back() + k * k);
    }
    g_.resize(g_offset_.back());
    h_.resize(linear_ ? g_offset_.back() : 0);
    // One candidate row per column: the products over all candidates below read each row
    // once, contiguously (a product with the rows as stored made Eigen copy them all first).
    rows_t_ = c_.rows.transpose();
  }

  int rows(int c) const { return c_.row_offset[c + 1] - c_.row_offset[c]; }

  // M = M0 + the chosen candidates' information, everything else recomputed from it.
  void reset(const std::vector<int>& chosen) {
    M_ = M0_;
    for (int c : chosen) {
      const auto X = block(c);
      M_.noalias() += X.transpose() * X;
    }
    Minv_ = M_.llt().solve(MatrixXd::Identity(n_, n_));
    P_t_.noalias() = Minv_ * rows_t_;  // column i: M^-1 x_i
    if (linear_) PW_t_.noalias() = W_ * P_t_;
    for (int c = 0; c < c_.size(); ++c) {
      const int k = rows(c), first = c_.row_offset[c];
      for (int r = 0; r < k; ++r)
        for (int s = 0; s < k; ++s) {
          g_[g_offset_[c] + r * k + s] = P_t_.col(first + r).dot(rows_t_.col(first + s));
          if (linear_) h_[g_offset_[c] + r * k + s] = PW_t_.col(first + r).dot(P_t_.col(first + s));
        }
    }
  }

  void add(int c) { change(c, +1); }
  void remove(int c) { change(c, -1); }

  // How much adding c improves the criterion (larger is better); E: lambda_min after.
  double gain(int c) const {
    const int k = rows(c);
    if (criterion_ == DesignCriterion::kE) return lambda_min_with(c);
    if (k == 1) {
      const double g = g_[g_offset_[c]];
      return linear_ ? h_[g_offset_[c]] / (1 + g) : std::log1p(g);
    }
    SmallMatrix G = Eigen::Map<const SmallMatrix>(&g_[g_offset_[c]], k, k);
    G.diagonal().array() += 1;
    if (!linear_) return std::log(G.determinant());
    const SmallMatrix H = Eigen::Map<const SmallMatrix>(&h_[g_offset_[c]], k, k);
    return G.ldlt().solve(H).trace();
  }

  // One reading per candidate (the rows are rank-one updates): the exchange step can look at
  // the design without candidate `c` before changing anything, and leave the state alone when
  // `c` is still the best choice, as it is for most steps once the design has settled.
  bool can_stage() const { return unit_rows_; }

  // Prepares removing c: the product over the candidates that the removal's update needs,
  // without applying it.
  void stage_removal(int c) {
    staged_ = c;
    prepare_rank_one(c_.rows.row(c_.row_offset[c]).transpose(), -1);
  }

  // The best available candidate (c included) were the staged candidate removed, and
  // whether it beats c clearly; apply_staged() then commits the removal.
  int best_staged(const std::vector<char>& available) const {
    const int c = staged_;
    int best_c = -1;
    if (criterion_ == DesignCriterion::kE) {
      best_c = best_e(available, true);
    } else {
      const bool rank_by_g = criterion_ == DesignCriterion::kD;  // log(1 + g) grows with g
      double best_gain = -std::numeric_limits<double>::infinity();
      for (int i = 0; i < c_.size(); ++i) {
        if (!available[i] && i != c) continue;
        const double g = rank_by_g ? staged_g(i) : staged_gain(i);
        if (g > best_gain) {
          best_gain = g;
          best_c = i;
        }
      }
    }
    // Only a clear improvement counts, so that rounding cannot make the exchange cycle.
    const double old_gain = staged_gain(c);
    if (best_c != c && !(staged_gain(best_c) > old_gain + 1e-12 * std::abs(old_gain))) best_c = c;
    return best_c;
  }

  void apply_staged() {
    apply_rank_one();
    staged_ = -1;
  }

  // The best of the candidates marked available (ties: the lowest index).
  int best(const std::vector<char>& available) const {
    if (criterion_ == DesignCriterion::kE) return best_e(available);
    int best_c = -1;
    double best_gain = -std::numeric_limits<double>::infinity();
    // D with one reading per candidate: log(1 + g) is increasing in g, so g ranks alike.
    const bool rank_by_g = unit_rows_ && criterion_ == DesignCriterion::kD;
    for (int c = 0; c < c_.size(); ++c) {
      if (!available[c]) continue;
      const double g = rank_by_g ? g_[c] : gain(c);
      if (g > best_gain) {
        best_gain = g;
        best_c = c;
      }
    }
    return best_c;
  }

 private:
  Eigen::Block<const MatrixXd> block(int c) const {
    return c_.rows.middleRows(c_.row_offset[c], rows(c));
  }

  // g and h of candidate i after the staged removal (the update rank_one would write).
  double staged_g(int i) const {
    const double a = ab_(i, 0);
    return g_[i] + k_ * a * a;
  }
  double staged_gain(int i) const {
    if (criterion_ == DesignCriterion::kE) return lambda_min_with(i, true);
    const double g = staged_g(i);
    if (!linear_) return std::log1p(g);
    const double a = ab_(i, 0);
    return (h_[i] + 2 * k_ * a * ab_(i, 1) + k_ * k_ * uwu_ * a * a) / (1 + g);
  }

  double lambda_min_with(int c, bool staged = false) const {
    const auto X = block(c);
    const MatrixXd M = (staged ? M_staged_ : M_) + X.transpose() * X;
    return Eigen::SelfAdjointEigenSolver<MatrixXd>(M, Eigen::EigenvaluesOnly).eigenvalues()[0];
  }

  // E is not a smooth function of rank-one updates: the candidates are screened by their D
  // gain (information in the directions M^-1 weighs most), and the best few compared exactly.
  int best_e(const std::vector<char>& available, bool staged = false) const {
    std::vector<std::pair<double, int>>& ranked = ranked_;  // reused: no allocation per step
    ranked.clear();
    for (int c = 0; c < c_.size(); ++c)
      if (available[c] || (staged && c == staged_)) {
        const int k = rows(c);
        double trace = 0;
        if (staged)
          trace = staged_g(c);
        else
          for (int r = 0; r < k; ++r) trace += g_[g_offset_[c] + r * k + r];
        ranked.push_back({-trace, c});
      }
    const std::size_t keep = std::min<std::size_t>(ranked.size(), 32);
    std::partial_sort(ranked.begin(), ranked.begin() + keep, ranked.end());
    int best_c = -1;
    double best_value = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < keep; ++i) {
      const double v = lambda_min_with(ranked[i].second, staged);
      if (v > best_value || (v == best_value && ranked[i].second < best_c)) {
        best_value = v;
        best_c = ranked[i].second;
      }
    }
    return best_c;
  }

  void change(int c, double sign) {
    const auto X = block(c);
    for (int r = 0; r < X.rows(); ++r) rank_one(X.row(r).transpose(), sign);
  }

  // M += sign v v^T, by Sherman-Morrison on M^-1 and on every candidate's forms.
  void rank_one(const VectorXd& v, double sign) {
    prepare_rank_one(v, sign);
    apply_rank_one();
  }

  // The update's coefficients and the product over every candidate's rows (the costly part,
  // a pass over the 10^5 x n rows), kept in ab_, k_, uwu_ until apply_rank_one().
  void prepare_rank_one(const VectorXd& v, double sign) {
    v_ = v;
    sign_ = sign;
    u_.noalias() = Minv_ * v;
    const double denominator = 1 + sign * v.dot(u_);
    k_ = -sign / denominator;
    uz_.resize(n_, linear_ ? 2 : 1);
    uz_.col(0) = u_;
    uwu_ = 0;
    if (linear_) {
      uz_.col(1).noalias() = Minv_ * (W_ * u_);
      uwu_ = u_.dot(W_ * u_);
    }
    ab_.resize(rows_t_.cols(), uz_.cols());
    for (Eigen::Index i = 0; i < rows_t_.cols(); ++i) {
      ab_(i, 0) = rows_t_.col(i).dot(u_);
      if (linear_) ab_(i, 1) = rows_t_.col(i).dot(uz_.col(1));
    }
    if (criterion_ == DesignCriterion::kE) M_staged_ = M_ + sign * v * v.transpose();
  }

  void apply_rank_one() {
    const double k = k_, uwu = uwu_;
    Minv_.noalias() += k * u_ * u_.transpose();
    M_.noalias() += sign_ * v_ * v_.transpose();
    if (unit_rows_) {
      const auto a = ab_.col(0).array();
      Eigen::Map<Eigen::ArrayXd>(g_.data(), g_.size()) += k * a.square();
      if (linear_)
        Eigen::Map<Eigen::ArrayXd>(h_.data(), h_.size()) +=
            2 * k * a * ab_.col(1).array() + k * k * uwu * a.square();
      return;
    }
    for (int c2 = 0; c2 < c_.size(); ++c2) {
      const int kk = rows(c2), first = c_.row_offset[c2];
      for (int r = 0; r < kk; ++r)
        for (int s = 0; s < kk; ++s) {
          const double ar = ab_(first + r, 0), as = ab_(first + s, 0);
          g_[g_offset_[c2] + r * kk + s] += k * ar * as;
          if (linear_)
            h_[g_offset_[c2] + r * kk + s] +=
                k * (ar * ab_(first + s, 1) + ab_(first + r, 1) * as) + k * k * uwu * ar * as;
        }
    }
  }

  const DesignCandidates& c_;
  DesignCriterion criterion_;
  int n_;
  bool linear_ = false, unit_rows_ = true;
  MatrixXd W_, M0_, M_, Minv_, ab_, uz_, M_staged_;
  MatrixXd rows_t_, P_t_, PW_t_;  // candidate rows, M^-1 and W M^-1 times them, per column
  VectorXd u_, v_;
  double k_ = 0, uwu_ = 0, sign_ = 0;
  int staged_ = -1;
  mutable std::vector<std::pair<double, int>> ranked_;  // best_e's screening
  std::vector<int> g_offset_;
  std::vector<double> g_, h_;
};

}  // namespace

DesignResult choose_design(const DesignCandidates& candidates, const DesignSetup& setup,
                           const DesignOptions& options) {
  if (options.count < 1) throw std::invalid_argument("the number of measurements must be >= 1");
  if (candidates.size() < options.count)
    throw std::invalid_argument("only " + std::to_string(candidates.size()) + " candidates for " +
                                std::to_string(options.count) +
                                " measurements; draw more candidates");
  DesignResult result;
  ExchangeState state(candidates, setup, options.criterion);
  std::vector<char> available(candidates.size(), 1);
  state.reset({});
  for (int i = 0; i < options.count; ++i) {
    // The greedy start is the least design there is: it is finished even when asked to stop.
    if (!keep_going(options, "greedy", i, options.count)) result.stopped = true;
    const int c = state.best(available);
    state.add(c);
    available[c] = 0;
    result.chosen.push_back(c);
  }
  // Values are compared through the same function throughout, so that "better" means better.
  const auto value = [&](const std::vector<int>& chosen) {
    const double v =
        criterion_value(options.criterion, design_information(candidates, chosen, setup), setup);
    return options.criterion == DesignCriterion::kD || options.criterion == DesignCriterion::kE
               ? v
               : -v;
  };
  result.greedy_value = value(result.chosen);
  double current = result.greedy_value;
  for (int pass = 0; pass < options.max_passes && !result.stopped; ++pass) {
    ++result.passes;
    state.reset(result.chosen);  // rounding errors of the updates do not accumulate
    const std::vector<int> pass_start = result.chosen;
    int changed = 0;
    for (int j = 0; j < options.count; ++j) {
      // Stopped between exchanges, the design holds count distinct candidates, each
      // exchange so far an improvement (or none): the best found so far.
      if (!keep_going(options, "exchange", j, options.count, pass + 1)) {
        result.stopped = true;
        break;
      }
      const int old = result.chosen[j];
      int best = old;
      if (state.can_stage()) {
        state.stage_removal(old);
        best = state.best_staged(available);
        if (best == old) continue;  // removing and adding it back would change nothing
        state.apply_staged();
      } else {
        state.remove(old);
        available[old] = 1;
        best = state.best(available);
        // Only a clear improvement counts, so that rounding cannot make the exchange cycle.
        if (best != old &&
            !(state.gain(best) > state.gain(old) + 1e-12 * std::abs(state.gain(old))))
          best = old;
      }
      state.add(best);
      available[old] = 1;
      available[best] = 0;
      if (best != old) {
        result.chosen[j] = best;
        ++changed;
      }
    }
    result.exchanges += changed;
    const double after = value(result.chosen);
    result.pass_values.push_back(
        std::max(current, after) *
        (options.criterion == DesignCriterion::kD || options.criterion == DesignCriterion::kE
             ? 1
             : -1));
    // A pass cut short that did not improve on its start gives its start back: the best
    // design found so far.
    if (result.stopped && !(after >= current)) result.chosen = pass_start;
    if (changed == 0 || !(after > current) || result.stopped) {
      current = std::max(current, after);
      break;
    }
    current = after;
  }
  const bool maximised =
      options.criterion == DesignCriterion::kD || options.criterion == DesignCriterion::kE;
  result.criterion_value = maximised ? current : -current;
  if (!maximised) result.greedy_value = -result.greedy_value;
  return result;
}

// ---------------------------------------------------------------------------------------
// The bound: Frank-Wolfe on the continuous relaxation

namespace {

// The relaxed criterion in minimised form (D: -log det M); +inf where M is not positive
// definite.
double relaxed_loss(DesignCriterion criterion, const MatrixXd& M, const MatrixXd& W) {
  const Eigen::LLT<MatrixXd> llt(M);
  if (llt.info() != Eigen::Success) return std::numeric_limits<double>::infinity();
  const VectorXd diagonal = llt.matrixLLT().diagonal();
  if (!(diagonal.array() > 0).all()) return std::numeric_limits<double>::infinity();
  if (criterion == DesignCriterion::kD) return -2 * diagonal.array().log().sum();
  return (W * llt.solve(MatrixXd::Identity(M.rows(), M.cols()))).trace();
}

}  // namespace

DesignBound design_bound(const DesignCandidates& candidates, const DesignSetup& setup,
                         const DesignOptions& options, const std::vector<int>& start,
                         int max_iterations, double relative_gap) {
  DesignBound out;
  const DesignCriterion criterion = options.criterion;
  if (criterion == DesignCriterion::kE) return out;
  const int count = options.count, size = candidates.size();
  if (static_cast<int>(start.size()) != count || count > size)
    throw std::invalid_argument("design_bound: the start must be a design of options.count");
  const int n = static_cast<int>(candidates.rows.cols());
  const MatrixXd W = criterion == DesignCriterion::kI ? setup.workspace_weight
                                                      : MatrixXd(MatrixXd::Identity(n, n) / n);
  const MatrixXd rows_t = candidates.rows.transpose();
  const auto information_of = [&](const std::vector<int>& chosen) {
    MatrixXd D = MatrixXd::Zero(n, n);
    for (int c : chosen)
      for (int r = candidates.row_offset[c]; r < candidates.row_offset[c + 1]; ++r)
        D.selfadjointView<Eigen::Lower>().rankUpdate(rows_t.col(r));
    return MatrixXd(D.selfadjointView<Eigen::Lower>());
  };
  VectorXd w = VectorXd::Zero(size);
  for (int c : start) w[c] = 1;
  MatrixXd data = information_of(start);  // sum of w_c X_c^T X_c
  double loss = relaxed_loss(criterion, setup.base_information + data, W);
  if (!std::isfinite(loss)) return out;  // a start that determines nothing bounds nothing
  double best_bound = -std::numeric_limits<double>::infinity();
  VectorXd score(size), per_row;
  std::vector<int> order(size);
  MatrixXd B, C;
  for (int it = 0; it < max_iterations; ++it) {
    if (!keep_going(options, "bound", it, max_iterations)) {
      out.stopped = true;
      break;
    }
    out.iterations = it + 1;
    // score_c = -d loss / d w_c: x^T M^-1 x (D) or x^T M^-1 W M^-1 x (A, I), over c's rows.
    const MatrixXd M = setup.base_information + data;
    const MatrixXd Minv = M.llt().solve(MatrixXd::Identity(n, n));
    B.noalias() = Minv * rows_t;
    if (criterion == DesignCriterion::kD) {
      per_row = (B.array() * rows_t.array()).colwise().sum().transpose();
    } else {
      C.noalias() = W * B;
      per_row = (B.array() * C.array()).colwise().sum().transpose();
    }
    for (int c = 0; c < size; ++c)
      score[c] = per_row
                     .segment(candidates.row_offset[c],
                              candidates.row_offset[c + 1] - candidates.row_offset[c])
                     .sum();
    // The best vertex of {0 <= w <= 1, sum w = count}: the count highest scores.
    std::iota(order.begin(), order.end(), 0);
    std::nth_element(order.begin(), order.begin() + (count - 1), order.end(),
                     [&](int a, int b) { return score[a] > score[b]; });
    const std::vector<int> vertex(order.begin(), order.begin() + count);
    double vertex_score = 0;
    for (int c : vertex) vertex_score += score[c];
    const double gap = vertex_score - w.dot(score);  // >= 0 by convexity
    best_bound = std::max(best_bound, loss - gap);
    // The Frank-Wolfe gap is not monotone: stop on what is certified so far.
    const double scale = criterion == DesignCriterion::kD ? n : std::abs(loss);
    if (loss - best_bound <= relative_gap * scale) break;
    // A pairwise step (Lacoste-Julien and Jaggi 2015): weight moves from the worst-scoring
    // candidate that has some to the best-scoring one that is not full. Unlike plain
    // Frank-Wolfe steps towards the vertex, which zigzag, it converges linearly here.
    int plus = -1, minus = -1;
    for (int c = 0; c < size; ++c) {
      if (w[c] < 1 - 1e-12 && (plus < 0 || score[c] > score[plus])) plus = c;
      if (w[c] > 1e-12 && (minus < 0 || score[c] < score[minus])) minus = c;
    }
    if (plus < 0 || minus < 0 || !(score[plus] > score[minus])) break;  // optimal
    const double t_max = std::min(1 - w[plus], w[minus]);
    const MatrixXd move = information_of({plus}) - information_of({minus});
    const auto loss_at = [&](double t) {
      return relaxed_loss(criterion, setup.base_information + data + t * move, W);
    };
    // Golden-section search for the step (the loss is convex along the segment).
    double lo = 0, hi = t_max;
    const double golden = 0.5 * (std::sqrt(5.0) - 1);
    double t1 = hi - golden * (hi - lo), t2 = lo + golden * (hi - lo);
    double f1 = loss_at(t1), f2 = loss_at(t2);
    for (int k = 0; k < 50; ++k) {
      if (f1 <= f2) {
        hi = t2, t2 = t1, f2 = f1;
        t1 = hi - golden * (hi - lo);
        f1 = loss_at(t1);
      } else {
        lo = t1, t1 = t2, f1 = f2;
        t2 = lo + golden * (hi - lo);
        f2 = loss_at(t2);
      }
    }
    // The full move (a candidate emptied or filled) when the loss still falls at its end.
    double t = 0.5 * (lo + hi), f = loss_at(t);
    const double f_end = loss_at(t_max);
    if (f_end <= f) t = t_max, f = f_end;
    if (!(f < loss)) break;                      // no progress left at double precision
    const bool fills = 1 - w[plus] <= w[minus];  // which bound the full move reaches
    w[plus] += t;
    w[minus] -= t;
    if (t == t_max) {  // exactly, so that the candidate counts as full or empty
      if (fills)
        w[plus] = 1;
      else
        w[minus] = 0;
    }
    data += t * move;
    loss = f;
  }
  const bool maximised = criterion == DesignCriterion::kD;
  out.bound = maximised ? -best_bound : best_bound;
  out.relaxed_value = maximised ? -loss : loss;
  return out;
}

double design_std_ratio_to_bound(DesignCriterion criterion, double value, const DesignBound& bound,
                                 int num_free) {
  if (!std::isfinite(bound.bound)) return std::numeric_limits<double>::quiet_NaN();
  if (criterion == DesignCriterion::kD) return std::exp((bound.bound - value) / (2.0 * num_free));
  return bound.bound > 0 ? std::sqrt(value / bound.bound)
                         : std::numeric_limits<double>::quiet_NaN();
}

std::vector<int> random_design(const DesignCandidates& candidates, int count, std::uint64_t seed) {
  // Candidates of the random configurations only, in order.
  std::vector<int> pool;
  for (int c = 0; c < candidates.size(); ++c)
    if (candidates.configuration[c] >= candidates.num_corners) pool.push_back(c);
  if (static_cast<int>(pool.size()) < count)
    throw std::invalid_argument("only " + std::to_string(pool.size()) +
                                " random candidates for a random design of " +
                                std::to_string(count));
  Random rng(derive_seed(seed, kRandomStream));
  for (int i = 0; i < count; ++i) {  // partial Fisher-Yates
    const int j = i + static_cast<int>(rng.uniform01() * (pool.size() - i));
    std::swap(pool[i], pool[j]);
  }
  pool.resize(count);
  return pool;
}

Measurements design_rows(const MeasurementModel& model, const DesignCandidates& candidates,
                         const std::vector<int>& chosen) {
  std::vector<int> order;  // configurations in order of first choice
  std::vector<int> row_of(candidates.configurations.rows(), -1);
  for (int c : chosen) {
    const int q = candidates.configuration[c];
    if (row_of[q] < 0) {
      row_of[q] = static_cast<int>(order.size());
      order.push_back(q);
    }
  }
  Measurements m;
  m.actuators.resize(order.size(), candidates.configurations.cols());
  m.readings = MatrixXd::Constant(order.size(), model.num_readings(),
                                  std::numeric_limits<double>::quiet_NaN());
  for (std::size_t r = 0; r < order.size(); ++r)
    m.actuators.row(r) = candidates.configurations.row(order[r]);
  for (int c : chosen) {
    const int s = candidates.sensor[c];
    m.readings.row(row_of[candidates.configuration[c]])
        .segment(model.sensor_reading_offset(s), model.sensors()[s]->num_readings())
        .setZero();
  }
  return m;
}

DesignRun run_design(const MeasurementModel& model, const DesignOptions& options,
                     const Measurements* existing) {
  DesignRun run;
  run.setup = make_design_setup(model, options, existing);
  run.candidates = make_design_candidates(model, run.setup, options);
  run.result = choose_design(run.candidates, run.setup, options);
  run.rows = design_rows(model, run.candidates, run.result.chosen);
  return run;
}

}  // namespace kincal
