#include "kincal/framework/least_squares/stationarity.hpp"

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <limits>

namespace kincal {

namespace {

// The estimated rounding error of residual i (see cost_rounding).
double residual_rounding(const VectorXd& x, const VectorXd& r, const MatrixXd& J, Eigen::Index i) {
  double terms = std::abs(r[i]);
  for (Eigen::Index j = 0; j < x.size(); ++j) terms += std::abs(J(i, j) * x[j]);
  return std::numeric_limits<double>::epsilon() * terms;
}

}  // namespace

double cost_rounding(const VectorXd& x, const VectorXd& r, const MatrixXd& J) {
  double sum = 0;
  for (Eigen::Index i = 0; i < r.size(); ++i) {
    const double e = residual_rounding(x, r, J, i);
    sum += std::abs(r[i]) * e + 0.5 * e * e;
  }
  return sum;
}

double relative_gradient(const VectorXd& x, const VectorXd& r, const MatrixXd& J,
                         const SolverOptions& options) {
  if (!r.allFinite() || !J.allFinite()) return HUGE_VAL;
  const bool bounded = options.lower_bounds.has_value() && options.upper_bounds.has_value();
  const double residual_norm = r.norm();
  double largest = 0;
  for (Eigen::Index j = 0; j < J.cols(); ++j) {
    const double column = J.col(j).norm();
    if (dead_column(column, x[j], residual_norm)) continue;
    largest =
        std::max(largest, relative_gradient_entry(J.col(j).dot(r), column, residual_norm, x[j],
                                                  bounded ? (*options.lower_bounds)[j] : -HUGE_VAL,
                                                  bounded ? (*options.upper_bounds)[j] : HUGE_VAL));
  }
  return largest;
}

Stationarity measure_stationarity(const VectorXd& x, const VectorXd& r, const MatrixXd& J,
                                  const SolverOptions& options) {
  StationarityScratch scratch(static_cast<int>(r.size()), static_cast<int>(x.size()));
  Stationarity s;
  measure_stationarity(x, r, J, options, scratch, s);
  return s;
}

void measure_stationarity(const VectorXd& x, const VectorXd& r, const MatrixXd& J,
                          const SolverOptions& options, StationarityScratch& scratch,
                          Stationarity& s) {
  const int n = static_cast<int>(x.size());
  const double eps = std::numeric_limits<double>::epsilon();
  s.cost = 0.5 * r.squaredNorm();
  s.gradient_norm = s.gradient_rounding = s.predicted_relative_decrease = s.relative_step = 0;
  s.relative_gradient = s.raw_relative_gradient = 0;
  s.cost_rounding = 0;
  s.gauss_newton_trusted = true;
  s.dead_parameters.clear();
  s.num_free = 0;
  s.finite = r.allFinite() && J.allFinite();
  if (!s.finite) {  // nothing to measure: every test fails (see Stationarity::finite)
    s.gradient_norm = s.relative_gradient = s.raw_relative_gradient = s.relative_step = HUGE_VAL;
    s.predicted_relative_decrease = 1;
    s.gauss_newton_trusted = false;
    return;
  }
  const double residual_norm = std::sqrt(2 * s.cost);
  VectorXd& g = scratch.gradient;
  g.noalias() = J.transpose() * r;
  // Each residual's estimated error, kept in `image` until the Cauchy point needs it.
  VectorXd& residual_error = scratch.image;
  for (Eigen::Index i = 0; i < r.size(); ++i) {
    residual_error[i] = residual_rounding(x, r, J, i);
    s.cost_rounding +=
        std::abs(r[i]) * residual_error[i] + 0.5 * residual_error[i] * residual_error[i];
  }
  const bool bounded = options.lower_bounds.has_value() && options.upper_bounds.has_value();

  std::vector<int>& free = scratch.free;
  free.clear();
  for (int j = 0; j < n; ++j) {
    double projected = g[j];
    bool held = false;  // at a bound, with the gradient pushing outwards
    if (bounded) {
      const double lo = (*options.lower_bounds)[j], hi = (*options.upper_bounds)[j];
      projected = x[j] - std::min(hi, std::max(lo, x[j] - g[j]));
      // Held at a bound when the gradient pushes outwards and the bound is within
      // kBoundTolerance: an interior-point method's iterate lies just inside it, never on it.
      const double near_lo = kBoundTolerance * (std::abs(lo) + 1);
      const double near_hi = kBoundTolerance * (std::abs(hi) + 1);
      held = (x[j] - lo <= near_lo && g[j] > 0) || (hi - x[j] <= near_hi && g[j] < 0);
    }
    s.gradient_norm = std::max(s.gradient_norm, std::abs(projected));
    // The dot product's own rounding and the residuals' errors carried through J^T.
    double rounding = 0;
    for (Eigen::Index i = 0; i < r.size(); ++i)
      rounding += std::abs(J(i, j)) *
                  (static_cast<double>(r.size()) * eps * std::abs(r[i]) + residual_error[i]);
    s.gradient_rounding = std::max(s.gradient_rounding, rounding);
    const double column = J.col(j).norm();
    // A dead parameter's direction says nothing (the plateau test names it): left out of the
    // gradient test as of the steps below, held or not.
    const bool dead = dead_column(column, x[j], residual_norm);
    if (!dead && column > 0 && residual_norm > 0) {
      // This entry's rounding error discounted, relative to the same scale.
      const double entry = relative_gradient_entry(g[j], column, residual_norm, x[j],
                                                   bounded ? (*options.lower_bounds)[j] : -HUGE_VAL,
                                                   bounded ? (*options.upper_bounds)[j] : HUGE_VAL);
      s.relative_gradient =
          std::max(s.relative_gradient, entry - rounding / column / residual_norm);
      s.raw_relative_gradient = std::max(s.raw_relative_gradient, entry);
    }
    if (held) continue;
    if (dead) {
      s.dead_parameters.push_back(j);
      continue;
    }
    free.push_back(j);
  }
  s.num_free = static_cast<int>(free.size() + s.dead_parameters.size());
  if (free.empty() || s.cost == 0) return;

  // The Cauchy point of the Gauss-Newton model along -g, over the free, live parameters.
  VectorXd& g_free = scratch.free_gradient;
  g_free.setZero();
  for (int j : free) g_free[j] = g[j];
  const double g2 = g_free.squaredNorm();
  const double x_norm = x.norm();
  s.gauss_newton_trusted = false;
  if (g2 == 0) return;
  scratch.image.noalias() = J * g_free;
  const double jg2 = scratch.image.squaredNorm();
  if (jg2 == 0) {  // the model is linear along -g: it promises everything
    s.predicted_relative_decrease = 1;
    s.relative_step = std::numeric_limits<double>::infinity();
    return;
  }
  s.predicted_relative_decrease = std::min(1.0, 0.5 * g2 * g2 / jg2 / s.cost);
  s.relative_step = g2 * std::sqrt(g2) / jg2 / (x_norm + options.parameter_tolerance);
  // The Gauss-Newton step promises at least the Cauchy decrease and is at least as long
  // (Powell's dogleg lemma), so it can only change a verdict when a Cauchy test passes.
  if (!s.cost_test(options) && !s.step_test(options)) return;

  // The Gauss-Newton step over the free, live columns, each scaled to unit norm so that rank
  // decisions do not depend on units: dx = -A^+ r (minimum norm), decrease 1/2 |A y|^2. Through
  // the triangular factor of [A r | 0], formed block by block (no copy of A): its leading
  // k x k block is A's R, the next column's head is Q^T r, and |A y| = |R y|.
  const Eigen::Index k = static_cast<Eigen::Index>(free.size());
  VectorXd& column_norm = scratch.free_gradient;  // reused: one entry per free column
  for (Eigen::Index c = 0; c < k; ++c) column_norm[c] = J.col(free[c]).norm();
  MatrixXd& block = scratch.block;
  TriangularFactor& factor = scratch.factor;
  factor.reset();
  block.setZero();
  for (Eigen::Index begin = 0; begin < r.size(); begin += block.rows()) {
    const Eigen::Index rows = std::min(block.rows(), r.size() - begin);
    for (Eigen::Index c = 0; c < k; ++c)
      block.col(c).head(rows) = J.col(free[c]).segment(begin, rows) / column_norm[c];
    block.col(k).head(rows) = r.segment(begin, rows);
    factor.add_rows(block.topRows(rows));
  }
  const auto R = factor.R().topLeftCorner(k, k);
  VectorXd& y = scratch.step;
  y.head(k) = factor.R().col(k).head(k);
  const double smallest = R.diagonal().cwiseAbs().minCoeff();
  const double largest = R.diagonal().cwiseAbs().maxCoeff();
  if (smallest > std::sqrt(eps) * largest) {
    // Clearly of full rank: the triangular solve, without allocating (lm measures inside its
    // loop). A hidden near-singularity would give a step too long to trust, refused below.
    R.triangularView<Eigen::Upper>().solveInPlace(y.head(k));
  } else {
    Eigen::CompleteOrthogonalDecomposition<MatrixXd> cod;
    cod.setThreshold(eps * static_cast<double>(std::max(r.size(), k)));
    cod.compute(R);
    y.head(k) = cod.solve(factor.R().col(k).head(k));
  }
  double step2 = 0;
  for (Eigen::Index c = 0; c < k; ++c) step2 += std::pow(y[c] / column_norm[c], 2);
  if (std::sqrt(step2) > x_norm + 1) return;  // too long to mean anything: keep Cauchy's
  s.gauss_newton_trusted = true;
  double decrease2 = 0;  // |R y|^2, entry by entry: no temporary
  for (Eigen::Index i = 0; i < k; ++i)
    decrease2 += std::pow(R.row(i).tail(k - i).dot(y.segment(i, k - i)), 2);
  s.predicted_relative_decrease = std::min(1.0, decrease2 / r.squaredNorm());
  s.relative_step = std::sqrt(step2) / (x_norm + options.parameter_tolerance);
}

std::string describe_parameters(const std::vector<int>& indices,
                                const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t k = 0; k < indices.size(); ++k) {
    if (k == 8 && indices.size() > 9) {
      out += ", ... (" + std::to_string(indices.size()) + " in all)";
      break;
    }
    const int i = indices[k];
    out +=
        (k ? ", " : "") + (i < static_cast<int>(names.size()) ? names[i] : "x" + std::to_string(i));
  }
  return out;
}

}  // namespace kincal
