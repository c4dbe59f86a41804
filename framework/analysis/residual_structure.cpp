// The residuals' shape: neighbours, the fixed parameters, the readings' spread
// (residual_structure.hpp).
#include "kincal/framework/analysis/residual_structure.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "kincal/framework/base/statistics.hpp"

namespace kincal {

bool ResidualStructure::neighbour_structured() const {
  return tested && neighbour_fraction > kNeighbourStructured && neighbour_z > kNeighbourZ;
}

bool ResidualStructure::fixed_structured() const {
  return tested && fixed_directions > 0 && fixed_fraction > kFixedStructured &&
         fixed_p < kFixedProbability;
}

namespace {

// Evenly spaced configurations, at most kStructureSampleConfigurations.
Measurements sample_of(const Measurements& data) {
  const int m = data.size();
  const int stride =
      std::max(1, (m + kStructureSampleConfigurations - 1) / kStructureSampleConfigurations);
  if (stride == 1) return data;
  std::vector<int> rows;
  for (int r = 0; r < m; r += stride) rows.push_back(r);
  Measurements out;
  out.actuators = data.actuators(rows, Eigen::all);
  out.readings = data.readings(rows, Eigen::all);
  return out;
}

// phi and its z over nearest neighbours in scaled actuator space; `r` configurations x
// readings, NaN where missing, each column already divided by its unit's RMS.
void neighbour_measure(const MatrixXd& actuators, const MatrixXd& r, ResidualStructure& out) {
  const int m = static_cast<int>(actuators.rows());
  MatrixXd q = actuators;
  for (int a = 0; a < q.cols(); ++a) {
    const double mean = q.col(a).mean();
    const double spread = std::sqrt((q.col(a).array() - mean).square().mean());
    q.col(a) = (q.col(a).array() - mean) / (spread > 0 ? spread : 1.0);
  }
  double shared = 0, total = 0, distance = 0;
  int reading_pairs = 0;
  for (int c = 0; c < m; ++c) {
    int nearest = -1;
    double best = std::numeric_limits<double>::infinity();
    for (int d = 0; d < m; ++d) {
      if (d == c) continue;
      const double d2 = (q.row(c) - q.row(d)).squaredNorm();
      if (d2 < best) {
        best = d2;
        nearest = d;
      }
    }
    if (nearest < 0) continue;
    bool any = false;
    for (int i = 0; i < r.cols(); ++i) {
      const double a = r(c, i), b = r(nearest, i);
      if (std::isnan(a) || std::isnan(b)) continue;
      shared += a * b;
      total += 0.5 * (a * a + b * b);
      ++reading_pairs;
      any = true;
    }
    if (any) {
      ++out.pairs;
      distance += std::sqrt(best);
    }
  }
  if (reading_pairs == 0 || !(total > 0)) return;
  out.neighbour_fraction = shared / total;
  // Each pair's product has standard deviation s^2 under independent noise; mutual
  // neighbours count twice, hence P / 2 independent products.
  out.neighbour_z = out.neighbour_fraction * std::sqrt(0.5 * reading_pairs);
  out.mean_neighbour_distance = distance / out.pairs;
}

}  // namespace

ResidualStructure analyze_residual_structure(const CalibrationProblem& problem, const VectorXd& x) {
  ResidualStructure out;
  const MeasurementModel& model = problem.model();
  const Measurements sample = sample_of(problem.data());
  const int k = model.num_readings();
  const int n_all = model.parameters().size();
  std::vector<int> all(static_cast<std::size_t>(n_all));
  std::iota(all.begin(), all.end(), 0);
  const CalibrationProblem every(problem.model_ptr(), sample, problem.full_parameters(x), all);
  VectorXd r;
  MatrixXd J;
  std::string why;
  if (!every.evaluate(every.initial_free_parameters(), &r, &J, &why)) {
    out.not_tested = "the residuals cannot be evaluated: " + why;
    return out;
  }
  const std::vector<int> rows = sample.present_rows();
  const int n_free = static_cast<int>(problem.free_indices().size());
  if (static_cast<int>(rows.size()) < n_free + 10 || sample.size() < 10) {
    out.not_tested = "too few readings beyond the free parameters";
    return out;
  }
  out.tested = true;

  // Per unit: the residuals' RMS against the readings' spread, unwhitened.
  const auto units = model.reading_units();
  const VectorXd& stds = model.reading_std();
  // The residuals' typical size is robust (1.4826 x the median |residual|, the RMS of Gaussian
  // noise): a few gross outliers that a robust loss set aside must not read as a model that
  // explains nothing, while rows shuffled between configurations move every residual.
  std::map<std::string, std::vector<double>> residual_sizes;
  std::map<std::string, double> spread_sum;
  std::map<std::string, long> count;
  for (int i = 0; i < k; ++i) {
    double mean = 0;
    int present = 0;
    for (int c = 0; c < sample.size(); ++c)
      if (!std::isnan(sample.readings(c, i))) {
        mean += sample.readings(c, i);
        ++present;
      }
    if (present == 0) continue;
    mean /= present;
    for (int c = 0; c < sample.size(); ++c) {
      const double v = sample.readings(c, i);
      if (std::isnan(v)) continue;
      const double residual = r[c * k + i] * stds[i];
      residual_sizes[units[i]].push_back(std::abs(residual));
      spread_sum[units[i]] += (v - mean) * (v - mean);
      ++count[units[i]];
    }
  }
  for (const auto& [unit, sum] : spread_sum) {
    const double spread = std::sqrt(sum / count[unit]);
    // Readings that do not vary (a socket's zeros) have no spread to explain.
    if (!(spread > 0)) continue;
    out.reading_spread[unit] = spread;
    auto& sizes = residual_sizes[unit];
    const auto middle = sizes.begin() + static_cast<std::ptrdiff_t>(sizes.size() / 2);
    std::nth_element(sizes.begin(), middle, sizes.end());
    out.unexplained_spread[unit] = 1.4826 * *middle / spread;
  }

  // Neighbours: each reading's residual in its unit's RMS, so that mm and rad weigh alike.
  MatrixXd per_config(sample.size(), k);
  std::map<std::string, double> unit_rms;
  std::map<std::string, long> unit_count;
  for (int c = 0; c < sample.size(); ++c)
    for (int i = 0; i < k; ++i)
      if (!std::isnan(sample.readings(c, i))) {
        unit_rms[units[i]] += r[c * k + i] * r[c * k + i];
        ++unit_count[units[i]];
      }
  for (auto& [unit, sum] : unit_rms) sum = std::sqrt(sum / unit_count[unit]);
  for (int c = 0; c < sample.size(); ++c)
    for (int i = 0; i < k; ++i)
      per_config(c, i) = std::isnan(sample.readings(c, i)) || !(unit_rms[units[i]] > 0)
                             ? NAN
                             : r[c * k + i] / unit_rms[units[i]];
  neighbour_measure(sample.actuators, per_config, out);

  // The fixed parameters' columns beyond the free ones' span, scaled to unit norm.
  const VectorXd rp = r(rows);
  const MatrixXd Jp = J(rows, Eigen::all);
  std::vector<bool> is_free(static_cast<std::size_t>(n_all), false);
  for (int i : problem.free_indices()) is_free[static_cast<std::size_t>(i)] = true;
  std::vector<int> free_cols, fixed_cols;
  for (int j = 0; j < n_all; ++j)
    if (Jp.col(j).norm() > 0)
      (is_free[static_cast<std::size_t>(j)] ? free_cols : fixed_cols).push_back(j);
  MatrixXd F = Jp(Eigen::all, free_cols);
  for (int j = 0; j < F.cols(); ++j) F.col(j) /= F.col(j).norm();
  Eigen::ColPivHouseholderQR<MatrixXd> free_qr(F);
  free_qr.setThreshold(1e-10);
  const int rank_free = static_cast<int>(free_qr.rank());
  // The thin Q (rows x rank): the full one would be rows x rows, 8 GB at 32 000 readings.
  const MatrixXd Qf = free_qr.householderQ() * MatrixXd::Identity(F.rows(), rank_free);
  const VectorXd r_perp = rp - Qf * (Qf.transpose() * rp);
  const double rss = r_perp.squaredNorm();
  if (fixed_cols.empty() || !(rss > 0)) {
    out.fixed_directions = 0;
    return out;
  }
  MatrixXd X(Jp.rows(), 0);
  std::vector<std::string> names;
  for (int j : fixed_cols) {
    VectorXd c = Jp.col(j) / Jp.col(j).norm();
    c -= Qf * (Qf.transpose() * c);
    // A fixed parameter the free ones duplicate adds nothing (what identifiability fixed).
    if (c.norm() < 1e-6) continue;
    X.conservativeResize(Eigen::NoChange, X.cols() + 1);
    X.col(X.cols() - 1) = c;
    names.push_back(model.parameters()[j].name);
  }
  if (X.cols() == 0) return out;
  Eigen::ColPivHouseholderQR<MatrixXd> fixed_qr(X);
  fixed_qr.setThreshold(1e-8);
  const int p = static_cast<int>(fixed_qr.rank());
  const MatrixXd Qx = fixed_qr.householderQ() * MatrixXd::Identity(X.rows(), p);
  const double explained = (Qx.transpose() * r_perp).squaredNorm();
  out.fixed_directions = p;
  out.fixed_fraction = explained / rss;
  const int dof = static_cast<int>(rp.size()) - rank_free - p;
  out.fixed_test_dof = std::max(dof, 0);
  // The F-test: the noise's variance is estimated from the dof residual degrees of freedom
  // left, so with few of them (40 gauge readings, 24 free and 14 fixed parameters: 2) a
  // large share explained is what noise gives. Without any left, the fixed columns span the
  // whole residual and explain all of it whatever it holds: nothing can be concluded.
  if (dof > 0 && rss - explained > 0)
    out.fixed_p = f_upper_tail((explained / p) / ((rss - explained) / dof), p, dof);
  else
    out.fixed_p = 1;
  for (int j = 0; j < X.cols(); ++j) {
    const double share = std::pow(X.col(j).dot(r_perp), 2) / X.col(j).squaredNorm() / rss;
    if (!(share <= out.dominant_fixed_fraction)) {
      out.dominant_fixed_fraction = share;
      out.dominant_fixed = names[static_cast<std::size_t>(j)];
    }
  }
  return out;
}

}  // namespace kincal
