#pragma once
// Parameter uncertainty of a least-squares fit from its Jacobian.

#include "framework/types.hpp"

namespace kincal {

/// sigma^2 (J^T J)^-1, computed from the SVD of J (never by forming J^T J, whose condition
/// number is the square of J's). Singular values below rcond * s_max are treated as zero,
/// giving the pseudo-inverse on the identifiable subspace.
MatrixXd parameter_covariance(const MatrixXd& J, double sigma, double rcond = 1e-12);

}  // namespace kincal
