#include "framework/uncertainty.hpp"

#include <Eigen/SVD>

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

}  // namespace kincal
