#include "kincal/framework/least_squares/uncertainty.hpp"

#include "kincal/framework/base/triangular_factor.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace kincal {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Huber's kappa / mean(psi') for the residuals of an M-estimate with n parameters; exactly 1
// without a loss (psi' = 1 everywhere).
double robust_factor(const VectorXd& residuals, const RobustLoss& loss, int n) {
  const int m = static_cast<int>(residuals.size());
  if (loss.kind == RobustLoss::Kind::kNone || m == 0) return 1.0;
  VectorXd psi_prime(m);
  for (int i = 0; i < m; ++i) {
    const double s = residuals[i] * residuals[i];
    const auto rho = loss.evaluate(s);
    psi_prime[i] = rho[1] + 2 * s * rho[2];  // d/dr (rho'(r^2) r)
  }
  const double mean = psi_prime.mean();
  if (!(mean > 0)) return kNaN;
  const double variance = m > 1 ? (psi_prime.array() - mean).square().sum() / (m - 1) : 0.0;
  const double kappa = 1 + static_cast<double>(n) / m * variance / (mean * mean);
  return kappa / mean;
}

// The square roots of the covariance's diagonal: NaN where the variance is NaN (not
// determined), 0 where rounding made it slightly negative.
VectorXd std_from(const MatrixXd& covariance) {
  VectorXd std(covariance.rows());
  for (Eigen::Index i = 0; i < std.size(); ++i) {
    const double v = covariance(i, i);
    std[i] = std::isnan(v) ? kNaN : std::sqrt(std::max(v, 0.0));
  }
  return std;
}

// covariance_ij / (std_i std_j); 0 where a std is 0, NaN where one is NaN.
MatrixXd correlation_from(const MatrixXd& covariance, const VectorXd& std) {
  const Eigen::Index n = std.size();
  MatrixXd correlation = MatrixXd::Zero(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j)
      if (std::isnan(std[i]) || std::isnan(std[j]))
        correlation(i, j) = kNaN;
      else if (std[i] > 0 && std[j] > 0)
        correlation(i, j) = covariance(i, j) / (std[i] * std[j]);
  return correlation;
}

}  // namespace

MatrixXd parameter_covariance(const MatrixXd& J, double sigma, double rcond) {
  const Eigen::Index n = J.cols();
  // No parameter: nothing to estimate (Eigen's SVD of an m x 0 matrix is not defined).
  if (n == 0) return MatrixXd(0, 0);
  // No reading, a Jacobian that is zero (no reading depends on any parameter) or not
  // finite: nothing is determined, which is not a variance of 0.
  if (J.rows() == 0 || !J.allFinite() || J.isZero(0)) return MatrixXd::Constant(n, n, kNaN);
  // The SVD of J's triangular factor: the same singular values and V without copying J.
  const Eigen::JacobiSVD<MatrixXd> svd(triangular_factor(J), Eigen::ComputeThinV);
  const VectorXd& s = svd.singularValues();
  const double threshold = rcond * (s.size() ? s[0] : 0.0);
  VectorXd inv_s2 = VectorXd::Zero(s.size());
  for (int i = 0; i < s.size(); ++i)
    if (s[i] > threshold) inv_s2[i] = 1.0 / (s[i] * s[i]);
  const MatrixXd& V = svd.matrixV();
  MatrixXd covariance = sigma * sigma * V * inv_s2.asDiagonal() * V.transpose();
  // A parameter no reading depends on (a zero column) is not determined at all: the
  // pseudo-inverse would give it a variance of 0, as if it were known exactly.
  for (Eigen::Index i = 0; i < n; ++i)
    if (J.col(i).isZero(0)) {
      covariance.row(i).setConstant(kNaN);
      covariance.col(i).setConstant(kNaN);
    }
  return covariance;
}

ParameterUncertainty estimate_uncertainty(const MatrixXd& J, const VectorXd& residuals,
                                          const RobustLoss& loss, double rcond) {
  ParameterUncertainty u;
  const int m = static_cast<int>(J.rows());
  const int n = static_cast<int>(J.cols());
  // psi_i = rho'(r_i^2) r_i: the residual as the loss sees it (r_i itself without a loss).
  VectorXd psi(m);
  for (int i = 0; i < m; ++i) psi[i] = loss.evaluate(residuals[i] * residuals[i])[1] * residuals[i];
  u.degrees_of_freedom = m - n;
  u.effective_degrees_of_freedom = m - n;
  u.sigma = u.degrees_of_freedom > 0 ? std::sqrt(psi.squaredNorm() / u.degrees_of_freedom) : kNaN;
  u.robust_factor = robust_factor(residuals, loss, n);
  // Both covariances need only J^T J: one triangular factor serves them (the same matrix
  // parameter_covariance would form from J).
  const MatrixXd R = m > 0 ? triangular_factor(J) : J;
  u.covariance = parameter_covariance(R, u.robust_factor * u.sigma, rcond);
  u.std = std_from(u.covariance);
  // The correlation does not depend on sigma: take it from (J^T J)^-1, defined even for m = n.
  const MatrixXd unit = parameter_covariance(R, 1.0, rcond);
  u.correlation = correlation_from(unit, std_from(unit));
  return u;
}

namespace {

// [R / sigma; diag(sqrt(precision))], R J's triangular factor: the whitened data stacked with
// the prior's rows, as far as J^T J goes.
MatrixXd stack_prior(const MatrixXd& J, const VectorXd& precision, double sigma) {
  const MatrixXd R = triangular_factor(J);
  MatrixXd stacked = MatrixXd::Zero(R.rows() + J.cols(), J.cols());
  stacked.topRows(R.rows()) = R / sigma;
  stacked.bottomRows(J.cols()).diagonal() = precision.cwiseSqrt();
  return stacked;
}

// 1 - covariance_ii precision_i, clamped to [0, 1] against rounding.
VectorXd share_from(const MatrixXd& covariance, const VectorXd& precision) {
  VectorXd share(precision.size());
  for (int i = 0; i < precision.size(); ++i)
    share[i] = std::clamp(1.0 - covariance(i, i) * precision[i], 0.0, 1.0);
  return share;
}

}  // namespace

VectorXd data_share(const MatrixXd& J, const VectorXd& precision, double sigma, double rcond) {
  return share_from(parameter_covariance(stack_prior(J, precision, sigma), 1.0, rcond), precision);
}

ParameterUncertainty estimate_posterior_uncertainty(const MatrixXd& J, const VectorXd& residuals,
                                                    const VectorXd& precision,
                                                    const RobustLoss& loss, double rcond) {
  if (!(precision.array() > 0).any()) return estimate_uncertainty(J, residuals, loss, rcond);
  if (loss.kind != RobustLoss::Kind::kNone)
    throw std::invalid_argument("a prior with a robust loss is not supported");
  ParameterUncertainty u;
  const int m = static_cast<int>(J.rows());
  const int n = static_cast<int>(J.cols());
  u.degrees_of_freedom = m - n;
  // tr R = the number of parameters the data determine, at the stated noise: under the
  // model (prior and noise as stated) E|r|^2 = m - tr R at the MAP estimate.
  const double data_determined = data_share(J, precision, 1.0, rcond).sum();
  u.effective_degrees_of_freedom = m - data_determined;
  u.sigma = u.effective_degrees_of_freedom > 0
                ? std::sqrt(residuals.squaredNorm() / u.effective_degrees_of_freedom)
                : kNaN;
  u.robust_factor = 1;
  if (std::isfinite(u.sigma) && u.sigma > 0) {
    u.covariance = parameter_covariance(stack_prior(J, precision, u.sigma), 1.0, rcond);
    u.data_share = share_from(u.covariance, precision);
  } else {
    u.covariance = MatrixXd::Constant(n, n, kNaN);
    u.data_share = data_share(J, precision, 1.0, rcond);
  }
  u.std = std_from(u.covariance);
  u.prior_std = VectorXd::Zero(n);
  for (int i = 0; i < n; ++i)
    if (precision[i] > 0) u.prior_std[i] = 1.0 / std::sqrt(precision[i]);
  u.correlation = correlation_from(u.covariance, u.std);
  return u;
}

}  // namespace kincal
