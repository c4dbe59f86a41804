// Experiment design, second stage: choosing configurations by greedy selection and
// Fedorov-style exchange under rank-one updates of the information matrix.
#include "kincal/framework/design/experiment_design.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "kincal/framework/base/random.hpp"
#include "kincal/framework/design/design_stages.hpp"

namespace kincal {

using namespace design_detail;

namespace {

constexpr int kMaxRows = 16;
using SmallMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxRows, kMaxRows>;

// M^-1 and, per candidate, G = X M^-1 X^T and (A, I) H = X M^-1 W M^-1 X^T kept up to date
// under rank-one changes of M, for candidates of at most kMaxRows rows. A design with larger
// candidates (a camera view: up to n rows, the factor of its information) is "blocked": G
// and H would take n^2 per candidate and n^3 per update, so M^-1 is recomputed after each
// change instead, the candidates are screened by the first-order gain <M^-1, X^T X> (D; with
// M^-1 W M^-1 for A and I), and the best kScreened compared by their exact gain.
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
    for (int c = 0; c < c_.size(); ++c) {
      unit_rows_ = unit_rows_ && rows(c) == 1;
      blocked_ = blocked_ || rows(c) > kMaxRows;
    }
    if (blocked_) {
      // Each candidate's information X^T X, for the screening.
      information_.resize(c_.size());
      for (int c = 0; c < c_.size(); ++c) {
        const auto X = block(c);
        information_[c].noalias() = X.transpose() * X;
      }
      return;
    }
    g_offset_.push_back(0);
    for (int c = 0; c < c_.size(); ++c) g_offset_.push_back(g_offset_.back() + rows(c) * rows(c));
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
    if (blocked_) {
      if (linear_) screen_weight_.noalias() = Minv_ * W_ * Minv_;
      return;
    }
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

  void add(int c) { blocked_ ? change_blocked(c, +1) : change(c, +1); }
  void remove(int c) { blocked_ ? change_blocked(c, -1) : change(c, -1); }

  // How much adding c improves the criterion (larger is better); E: lambda_min after.
  double gain(int c) const {
    const int k = rows(c);
    if (criterion_ == DesignCriterion::kE) return lambda_min_with(c);
    if (blocked_) return blocked_gain(c);
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
  bool can_stage() const { return unit_rows_ && !blocked_; }

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
    if (blocked_) return best_blocked(available);
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
        if (blocked_)
          trace = Minv_.cwiseProduct(information_[c]).sum();
        else if (staged)
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

  // The exact gain of a blocked candidate: log det(I + G) (D) or trace((I + G)^-1 H) (A, I).
  double blocked_gain(int c) const {
    const auto X = block(c);
    const MatrixXd P = Minv_ * X.transpose();  // n x k
    MatrixXd G = X * P;
    G.diagonal().array() += 1;
    const Eigen::LLT<MatrixXd> llt(G);
    if (!linear_) return 2 * llt.matrixLLT().diagonal().array().log().sum();
    const MatrixXd H = P.transpose() * W_ * P;
    return llt.solve(H).trace();
  }

  // The best available blocked candidate: the kScreened with the largest first-order gain,
  // compared by their exact gain (ties: the lowest index).
  int best_blocked(const std::vector<char>& available) const {
    const MatrixXd& weight = linear_ ? screen_weight_ : Minv_;
    std::vector<std::pair<double, int>>& ranked = ranked_;
    ranked.clear();
    for (int c = 0; c < c_.size(); ++c)
      if (available[c]) ranked.push_back({-weight.cwiseProduct(information_[c]).sum(), c});
    const std::size_t keep = std::min<std::size_t>(ranked.size(), kScreened);
    std::partial_sort(ranked.begin(), ranked.begin() + keep, ranked.end());
    int best_c = -1;
    double best_value = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < keep; ++i) {
      const int c = ranked[i].second;
      const double v = blocked_gain(c);
      if (v > best_value || (v == best_value && c < best_c)) {
        best_value = v;
        best_c = c;
      }
    }
    return best_c;
  }

  void change_blocked(int c, double sign) {
    M_ += sign * information_[c];
    Minv_ = M_.llt().solve(MatrixXd::Identity(n_, n_));
    if (linear_) screen_weight_.noalias() = Minv_ * W_ * Minv_;
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
  bool linear_ = false, unit_rows_ = true, blocked_ = false;
  static constexpr std::size_t kScreened = 32;
  std::vector<MatrixXd> information_;  // blocked: each candidate's X^T X
  MatrixXd screen_weight_;             // blocked A, I: M^-1 W M^-1
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

}  // namespace kincal
