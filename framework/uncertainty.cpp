#include "framework/uncertainty.hpp"

#include <Eigen/SVD>
#include <cmath>
#include <limits>

namespace kincal {

MatrixXd parameter_covariance(const MatrixXd& J, double sigma, double rcond) {
  const Eigen::JacobiSVD<MatrixXd> svd(J, Eigen::ComputeThinV);
  const VectorXd& s = svd.singularValues();
  const double threshold = rcond * (s.size() ? s[0] : 0.0);
  VectorXd inv_s2 = VectorXd::Zero(s.size());
  for (int i = 0; i < s.size(); ++i)
    if (s[i] > threshold) inv_s2[i] = 1.0 / (s[i] * s[i]);
  const MatrixXd& V = svd.matrixV();
  return sigma * sigma * V * inv_s2.asDiagonal() * V.transpose();
}

ParameterUncertainty estimate_uncertainty(const MatrixXd& J, const VectorXd& residuals,
                                          double rcond) {
  ParameterUncertainty u;
  const int m = static_cast<int>(J.rows());
  const int n = static_cast<int>(J.cols());
  u.degrees_of_freedom = m - n;
  u.sigma = u.degrees_of_freedom > 0 ? std::sqrt(residuals.squaredNorm() / u.degrees_of_freedom)
                                     : std::numeric_limits<double>::quiet_NaN();
  u.covariance = parameter_covariance(J, u.sigma, rcond);
  u.std = u.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
  // The correlation does not depend on sigma: take it from (J^T J)^-1, defined even for m = n.
  const MatrixXd unit = parameter_covariance(J, 1.0, rcond);
  const VectorXd unit_std = unit.diagonal().cwiseMax(0.0).cwiseSqrt();
  u.correlation = MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (unit_std[i] > 0 && unit_std[j] > 0)
        u.correlation(i, j) = unit(i, j) / (unit_std[i] * unit_std[j]);
  return u;
}

}  // namespace kincal
