#include "kincal/framework/calibration/prior_problem.hpp"

#include <cmath>
#include <stdexcept>

namespace kincal {

VectorXd Prior::precision() const {
  VectorXd p = VectorXd::Zero(std.size());
  for (int i = 0; i < std.size(); ++i)
    if (std[i] > 0) p[i] = 1.0 / (std[i] * std[i]);
  return p;
}

Prior model_prior(const CalibrationProblem& problem) {
  Prior prior;
  prior.mean = problem.initial_free_parameters();
  prior.std.resize(problem.num_parameters());
  const ParameterSet& parameters = problem.model().parameters();
  for (std::size_t i = 0; i < problem.free_indices().size(); ++i)
    prior.std[static_cast<int>(i)] = parameters[problem.free_indices()[i]].prior_std;
  return prior;
}

PriorProblem::PriorProblem(const LeastSquaresProblem& data, Prior prior)
    : data_(data), prior_(std::move(prior)) {
  const int n = data_.num_parameters();
  if (prior_.mean.size() != n || prior_.std.size() != n)
    throw std::invalid_argument("the prior has " + std::to_string(prior_.std.size()) +
                                " entries, the problem " + std::to_string(n) + " parameters");
  for (int i = 0; i < n; ++i) {
    if (!(std::isfinite(prior_.std[i]) && prior_.std[i] >= 0))
      throw std::invalid_argument("prior std of parameter " + std::to_string(i) +
                                  " must be finite and >= 0 (0 = no prior)");
    if (prior_.std[i] > 0 && !std::isfinite(prior_.mean[i]))
      throw std::invalid_argument("prior mean of parameter " + std::to_string(i) +
                                  " must be finite");
    if (prior_.std[i] > 0) with_prior_.push_back(i);
  }
  const int k = data_.residuals_per_block();
  data_blocks_ = data_.num_residual_blocks();
  prior_blocks_ = k > 0 ? (static_cast<int>(with_prior_.size()) + k - 1) / k : 0;
}

bool PriorProblem::evaluate_block_warm(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                                       Eigen::Ref<MatrixXd>* jacobian, std::string* why,
                                       WarmStart& warm) const {
  if (block < data_blocks_)
    return data_.evaluate_block_warm(block, x, residuals, jacobian, why, warm);
  return evaluate_block(block, x, residuals, jacobian, why);
}

bool PriorProblem::evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                                  Eigen::Ref<MatrixXd>* jacobian, std::string* why) const {
  if (block < data_blocks_) return data_.evaluate_block(block, x, residuals, jacobian, why);
  // A prior block: residual j of the block is prior term (block - data_blocks_) * k + j.
  const int k = residuals_per_block();
  residuals.setZero();
  if (jacobian) jacobian->setZero();
  for (int j = 0; j < k; ++j) {
    const std::size_t term = static_cast<std::size_t>(block - data_blocks_) * k + j;
    if (term >= with_prior_.size()) break;  // padding: always 0
    const int i = with_prior_[term];
    residuals[j] = (x[i] - prior_.mean[i]) / prior_.std[i];
    if (jacobian) (*jacobian)(j, i) = 1.0 / prior_.std[i];
  }
  return true;
}

}  // namespace kincal
