#pragma once
// Parameter uncertainty of a least-squares fit from its Jacobian.

#include "kincal/framework/base/types.hpp"
#include "kincal/framework/least_squares/robust_loss.hpp"

namespace kincal {

/// sigma^2 (J^T J)^-1, computed from the SVD of J (never by forming J^T J, whose condition
/// number is the square of J's). Singular values below rcond * s_max are treated as zero,
/// giving the pseudo-inverse on the identifiable subspace.
MatrixXd parameter_covariance(const MatrixXd& J, double sigma, double rcond = 1e-12);

/// Uncertainty of a least-squares estimate with the noise level estimated from the fit.
struct ParameterUncertainty {
  int degrees_of_freedom = 0;  ///< m - n
  /// sigma_hat = sqrt(sum psi_i^2 / (m - n)) (mm), psi_i the residual after the robust loss
  /// (= r_i without one); NaN when m <= n (an exact fit says nothing about the noise).
  double sigma = 0;
  /// Huber's correction kappa / mean(psi'): 1 without a robust loss; NaN when mean(psi')
  /// <= 0 (the loss rejects most residuals: its delta is too small for this data).
  double robust_factor = 1;
  MatrixXd covariance;   ///< (robust_factor sigma_hat)^2 (J^T J)^-1 (n x n); NaN when either is
  VectorXd std;          ///< sqrt of its diagonal
  MatrixXd correlation;  ///< covariance_ij / (std_i std_j); 0 where a std is 0

  /// With a prior (estimate_posterior_uncertainty; without one these stay as below):
  /// m - tr(R), R = (J^T J + Lambda)^-1 J^T J at the stated noise; m - n without a prior.
  double effective_degrees_of_freedom = 0;
  /// Prior std per parameter (0 = none); empty without a prior.
  VectorXd prior_std;
  /// Per parameter, the share of its determination that comes from the data:
  /// 1 - posterior var / prior var = diag of the resolution matrix, in [0, 1]; 1 without a
  /// prior on the parameter. Empty without any prior.
  VectorXd data_share;
};

/// From the Jacobian J (m x n) and residuals r (m) at the estimate, for a fit that
/// minimised 1/2 sum rho(r_i^2) (`loss`; none = plain least squares, where this is the
/// ordinary sigma_hat^2 (J^T J)^-1 with sigma_hat^2 = |r|^2 / (m - n)).
///
/// With a robust loss the estimate is an M-estimator with psi(r) = rho'(r^2) r = w r (w the
/// IRLS weight). Its covariance is Huber's (Robust Statistics, 1981, sec. 7.6; the form of
/// R's MASS::rlm):
///   K^2 [sum psi_i^2 / (m - n)] / mean(psi')^2 (J^T J)^-1,
///   K = 1 + (n / m) var(psi') / mean(psi')^2.
/// psi is bounded (|psi| <= delta for Huber), so a gross outlier adds at most delta^2 to the
/// noise estimate, and psi' (0 beyond delta for Huber) removes the outliers' share of the
/// information. Compared over simulated outlier data with the IRLS-weighted alternative
/// sigma_hat^2 (J^T W J)^-1 this tracks the scatter of the estimates more closely; see
/// docs/calibrating-a-machine.md, section 5.
ParameterUncertainty estimate_uncertainty(const MatrixXd& J, const VectorXd& residuals,
                                          const RobustLoss& loss = {}, double rcond = 1e-12);

/// Posterior of a MAP estimate with a Gaussian prior of information diag(precision)
/// (Prior::precision(); 0 = no prior on that parameter), from the whitened data Jacobian J
/// and residuals at the estimate (docs/theory.md, "Prior knowledge"):
///   sigma_hat^2 = |r|^2 / (m - tr R),  R = (J^T J + Lambda)^-1 J^T J,
///   covariance  = (J^T J / sigma_hat^2 + Lambda)^-1,
///   data_share  = diag(covariance J^T J / sigma_hat^2) = 1 - covariance_ii precision_i.
/// sigma_hat is the ratio of the data's scatter to the stated reading std, and it scales the
/// data's information only: the prior's std is taken as stated. Without a prior this is
/// estimate_uncertainty exactly. Computed from the SVD of [J / sigma_hat; Lambda^1/2].
/// No robust loss: throws std::invalid_argument when both a prior and a loss are given.
ParameterUncertainty estimate_posterior_uncertainty(const MatrixXd& J, const VectorXd& residuals,
                                                    const VectorXd& precision,
                                                    const RobustLoss& loss = {},
                                                    double rcond = 1e-12);

/// The data share alone, at a given noise ratio (1 = the readings' noise as stated), e.g.
/// before any measurement: 1 - [(J^T J / sigma^2 + Lambda)^-1]_ii precision_i.
VectorXd data_share(const MatrixXd& J, const VectorXd& precision, double sigma = 1.0,
                    double rcond = 1e-12);

}  // namespace kincal
