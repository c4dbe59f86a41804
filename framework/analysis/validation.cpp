#include "kincal/framework/analysis/validation.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace kincal {

Validation validate_held_out(std::shared_ptr<const MeasurementModel> model,
                             const Measurements& data, const VectorXd& values,
                             const ValidationInput& input) {
  const int k = model->num_readings();
  if (input.noise_std.size() != k || !(input.noise_std.array() > 0).all() ||
      !input.noise_std.allFinite())
    throw std::invalid_argument("expected a noise std > 0 for every reading");
  const int n = static_cast<int>(input.parameters.size());
  if (input.covariance.rows() != n || input.covariance.cols() != n)
    throw std::invalid_argument("the covariance does not match the parameters");

  Validation v;
  v.configurations = data.size();
  v.parameter_uncertainty = n > 0;
  // The problem's residuals and Jacobian are divided by the model's reading_std: undo it, so
  // that everything below is in the readings' units.
  const CalibrationProblem problem(model, data, values, input.parameters);
  VectorXd r;
  MatrixXd J;
  std::string why;
  if (!problem.evaluate(problem.initial_free_parameters(), &r, n > 0 ? &J : nullptr, &why))
    throw std::runtime_error(why);
  std::vector<int> rows;  // measured readings, in (configuration, reading) order
  v.residuals = MatrixXd::Constant(data.size(), k, std::numeric_limits<double>::quiet_NaN());
  for (int c = 0; c < data.size(); ++c)
    for (int i = 0; i < k; ++i)
      if (!std::isnan(data.readings(c, i))) {
        rows.push_back(c * k + i);
        v.residuals(c, i) = r[c * k + i] * model->reading_std()[i];
      }
  const int m = static_cast<int>(rows.size());
  v.readings = m;
  if (m == 0) throw std::invalid_argument("no held-out reading was measured");

  // Whitened by the noise: r_w = D^-1/2 r, G = D^-1/2 J L with Sigma = L L^T, so that
  // C_w = I + G G^T and, by Woodbury, r_w^T C_w^-1 r_w = |r_w|^2 - |(I + G^T G)^-1/2 G^T r_w|^2
  // without forming the m x m matrix.
  VectorXd rw(m);
  MatrixXd G(m, n);
  MatrixXd L = MatrixXd::Zero(n, n);
  if (n > 0) {
    const Eigen::SelfAdjointEigenSolver<MatrixXd> eig(input.covariance);
    L = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
  }
  VectorXd predicted_var(m), parameter_var(m);
  for (int j = 0; j < m; ++j) {
    const int i = rows[j] % k;
    const double scale = model->reading_std()[i];  // back to the reading's unit
    rw[j] = r[rows[j]] * scale / input.noise_std[i];
    if (n > 0) {
      const Eigen::RowVectorXd jl = J.row(rows[j]) * scale * L;
      G.row(j) = jl / input.noise_std[i];
      parameter_var[j] = jl.squaredNorm();
    } else {
      parameter_var[j] = 0;
    }
    predicted_var[j] = input.noise_std[i] * input.noise_std[i] + parameter_var[j];
  }
  v.chi_square = rw.squaredNorm();
  if (n > 0) {
    const MatrixXd inner = MatrixXd::Identity(n, n) + G.transpose() * G;
    const VectorXd g = G.transpose() * rw;
    v.chi_square -= g.dot(inner.llt().solve(g));
  }
  v.standardized_rms = std::sqrt(v.chi_square / m);
  v.p_larger = chi_square_upper_tail(v.chi_square, m);
  v.p_smaller = 1 - v.p_larger;
  const double tail = input.significance / 2;
  v.verdict = v.p_larger < tail    ? "larger_than_predicted"
              : v.p_smaller < tail ? "smaller_than_predicted"
                                   : "consistent";

  const std::vector<std::string> names = model->reading_names(), units = model->reading_units();
  std::map<std::string, int> unit_count;
  v.per_reading.resize(k);
  for (int i = 0; i < k; ++i) {
    v.per_reading[i].name = names[i];
    v.per_reading[i].unit = units[i];
    v.per_reading[i].noise_std = input.noise_std[i];
  }
  for (int j = 0; j < m; ++j) {
    const int i = rows[j] % k;
    const double value = v.residuals(rows[j] / k, i);
    ReadingValidation& p = v.per_reading[i];
    ++p.count;
    p.rms += value * value;
    p.max = std::max(p.max, std::abs(value));
    p.predicted_rms += predicted_var[j];
    p.parameter_rms += parameter_var[j];
    v.rms_by_unit[units[i]] += value * value;
    v.max_by_unit[units[i]] = std::max(v.max_by_unit[units[i]], std::abs(value));
    ++unit_count[units[i]];
  }
  for (auto& p : v.per_reading)
    if (p.count) {
      p.rms = std::sqrt(p.rms / p.count);
      p.predicted_rms = std::sqrt(p.predicted_rms / p.count);
      p.parameter_rms = std::sqrt(p.parameter_rms / p.count);
    }
  for (auto& [unit, sum] : v.rms_by_unit) sum = std::sqrt(sum / unit_count[unit]);

  // No verdict on a statistic that is not a number: a reading such as 1e300 is finite, but
  // its square is not, and chi-square - inf - inf is NaN, which no comparison rejects.
  bool finite = std::isfinite(v.chi_square) && std::isfinite(v.standardized_rms) &&
                std::isfinite(v.p_larger) && std::isfinite(v.p_smaller);
  for (const auto& p : v.per_reading)
    finite = finite && std::isfinite(p.rms) && std::isfinite(p.max) &&
             std::isfinite(p.predicted_rms) && std::isfinite(p.parameter_rms) &&
             std::isfinite(p.noise_std);
  for (const auto& [unit, value] : v.rms_by_unit) finite = finite && std::isfinite(value);
  for (const auto& [unit, value] : v.max_by_unit) finite = finite && std::isfinite(value);
  if (!finite) {
    int worst = rows[0];
    for (int j : rows)
      if (!(std::abs(r[j] * model->reading_std()[j % k]) <=
            std::abs(r[worst] * model->reading_std()[worst % k])))
        worst = j;
    throw NonFiniteValidation(worst / k, worst % k, v.residuals(worst / k, worst % k),
                              names[worst % k]);
  }
  return v;
}

NonFiniteValidation::NonFiniteValidation(int configuration_index, int reading_index,
                                         double residual_value, const std::string& reading_name)
    : std::domain_error([&] {
        char text[40];
        std::snprintf(text, sizeof text, "%.3g", residual_value);
        return "the held-out statistics are not finite (no verdict): the largest residual, "
               "reading '" +
               reading_name + "' of configuration " + std::to_string(configuration_index + 1) +
               ", is " + text + "; expected readings on the scale of the machine";
      }()),
      configuration(configuration_index),
      reading(reading_index),
      residual(residual_value) {}

}  // namespace kincal
