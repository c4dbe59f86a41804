#pragma once
// Parameter uncertainty of a least-squares fit from its Jacobian.

#include "framework/types.hpp"

namespace kincal {

/// sigma^2 (J^T J)^-1, computed from the SVD of J (never by forming J^T J, whose condition
/// number is the square of J's). Singular values below rcond * s_max are treated as zero,
/// giving the pseudo-inverse on the identifiable subspace.
MatrixXd parameter_covariance(const MatrixXd& J, double sigma, double rcond = 1e-12);

/// Uncertainty of a least-squares estimate with the noise level estimated from the fit.
struct ParameterUncertainty {
  int degrees_of_freedom = 0;  ///< m - n
  /// sigma_hat = sqrt(|r|^2 / (m - n)), the residual standard deviation (mm); NaN when
  /// m <= n (an exact fit says nothing about the noise).
  double sigma = 0;
  MatrixXd covariance;   ///< sigma_hat^2 (J^T J)^-1 (n x n); NaN when sigma is
  VectorXd std;          ///< sqrt of its diagonal
  MatrixXd correlation;  ///< covariance_ij / (std_i std_j); 0 where a std is 0
};

/// From the Jacobian J (m x n) and residuals r (m) at the estimate. With a plain
/// least-squares fit |r|^2 = 2 * final cost.
ParameterUncertainty estimate_uncertainty(const MatrixXd& J, const VectorXd& residuals,
                                          double rcond = 1e-12);

}  // namespace kincal
