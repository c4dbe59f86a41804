#pragma once
// Maximum a posteriori estimation for any least-squares backend: a problem wrapper that
// appends one residual (x_i - mean_i) / std_i per parameter with a Gaussian prior, so that
// minimising 1/2 |r|^2 of the wrapper minimises
//   1/2 |r_data(x)|^2 + 1/2 sum_i ((x_i - mean_i) / std_i)^2,
// the negative log posterior when r_data is whitened (divided by the readings' noise std,
// CalibrationProblem does that with the model's reading_std). Every backend (gn, lm, ceres,
// ipopt, nlopt) then does MAP without knowing it.
//
// Blocks stay uniform (LeastSquaresProblem's contract): the data problem's blocks come first,
// then ceil(p / k) prior blocks of k residuals (k = the data problem's residuals_per_block, p
// the parameters with a prior), the last one padded with residuals that are always 0.
//
// Robust losses: a backend applies its loss to every residual, the prior's included, which
// would turn the Gaussian prior into a Huber or Cauchy one. kincal does not do that: calibrate
// refuses --loss together with a prior (docs/theory.md, "Prior knowledge").

#include <vector>

#include "kincal/framework/calibration/calibration_problem.hpp"
#include "kincal/framework/least_squares/least_squares_problem.hpp"

namespace kincal {

/// A Gaussian prior on the parameters of a problem: mean and std per parameter, in the
/// problem's parameter order and units; std 0 = no prior on that parameter.
struct Prior {
  VectorXd mean;
  VectorXd std;

  /// Whether any parameter has a prior.
  bool any() const { return (std.array() > 0).any(); }
  /// diag(1 / std^2), 0 where there is no prior: the prior's information matrix.
  VectorXd precision() const;
};

/// The prior the model states for the free parameters of `problem` (Parameter::prior_std),
/// centred on the problem's starting values (the model file's values).
Prior model_prior(const CalibrationProblem& problem);

class PriorProblem : public LeastSquaresProblem {
 public:
  /// `data` must outlive the wrapper. Throws std::invalid_argument when the prior's sizes do
  /// not match the problem, or a std is negative or not finite, or a mean is not finite.
  PriorProblem(const LeastSquaresProblem& data, Prior prior);

  int num_parameters() const override { return data_.num_parameters(); }
  int num_residual_blocks() const override { return data_blocks_ + prior_blocks_; }
  int residuals_per_block() const override { return data_.residuals_per_block(); }
  std::vector<std::string> parameter_names() const override { return data_.parameter_names(); }

  bool evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                      Eigen::Ref<MatrixXd>* jacobian, std::string* why) const override;
  /// The data problem's warm start; its blocks are evaluated with it, the others as they are.
  std::unique_ptr<WarmStart> make_warm_start() const override { return data_.make_warm_start(); }
  bool evaluate_block_warm(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                           Eigen::Ref<MatrixXd>* jacobian, std::string* why,
                           WarmStart& warm) const override;

  const LeastSquaresProblem& data_problem() const { return data_; }
  const Prior& prior() const { return prior_; }
  /// The first num_data_residuals() residuals are the data problem's, in its order.
  int num_data_residuals() const { return data_.num_residuals(); }
  /// Parameters with a prior, in parameter order: prior residual j is on parameter
  /// prior_parameters()[j], at row num_data_residuals() + j.
  const std::vector<int>& prior_parameters() const { return with_prior_; }

 private:
  const LeastSquaresProblem& data_;
  Prior prior_;
  std::vector<int> with_prior_;
  int data_blocks_ = 0;
  int prior_blocks_ = 0;
};

}  // namespace kincal
