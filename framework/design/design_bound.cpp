// Experiment design, the bound: the best value any design of the given size could reach, from
// the continuous relaxation solved by Frank-Wolfe.
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

}  // namespace kincal
