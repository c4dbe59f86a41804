#pragma once
// The Cramér-Rao prediction for one simulated scenario: what an efficient unbiased estimator
// would achieve given the scenario's configurations and noise level.

#include "kincal/framework/calibration/simulation.hpp"

namespace kincal::bench {

struct CramerRaoPrediction {
  bool ok = false;                     ///< false when J at the truth could not be computed
  double sigma = 0;                    ///< gauge noise standard deviation a / sqrt(3), mm
  double condition_number = 0;         ///< of J at the true parameters
  double parameter_mean_square = 0;    ///< trace(Cov) / n, mm^2
  double position_mean_square = 0;     ///< mean over validation poses of E|dt|^2, mm^2
  double orientation_mean_square = 0;  ///< mean over validation poses of E|dw|^2, rad^2
};

/// Cov = sigma^2 (J^T J)^-1 with J the scenario problem's Jacobian at the true free
/// parameters, and its propagation to the validation poses through J_pose_params (true
/// geometry, true poses). To first order the paper's Euler-angle orientation error is |dw|.
CramerRaoPrediction predict_cramer_rao(const Scenario& scenario);

}  // namespace kincal::bench
