#include "kincal/problems/scaled_problem.hpp"

#include <cmath>
#include <stdexcept>

namespace kincal::problems {

ScaledProblem::ScaledProblem(const LeastSquaresProblem& inner, double scale)
    : inner_(inner), scale_(scale) {
  if (!std::isfinite(scale) || scale == 0)
    throw std::invalid_argument("ScaledProblem: the scale must be finite and non-zero");
}

bool ScaledProblem::scaled(bool ok, Eigen::Ref<VectorXd> residuals,
                           Eigen::Ref<MatrixXd>* jacobian) const {
  if (!ok) return false;
  residuals *= scale_;
  if (jacobian) *jacobian *= scale_;
  return true;
}

bool ScaledProblem::evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                                   Eigen::Ref<MatrixXd>* jacobian, std::string* why) const {
  return scaled(inner_.evaluate_block(block, x, residuals, jacobian, why), residuals, jacobian);
}

bool ScaledProblem::evaluate_block_warm(int block, const VectorXd& x,
                                        Eigen::Ref<VectorXd> residuals,
                                        Eigen::Ref<MatrixXd>* jacobian, std::string* why,
                                        WarmStart& warm) const {
  return scaled(inner_.evaluate_block_warm(block, x, residuals, jacobian, why, warm), residuals,
                jacobian);
}

}  // namespace kincal::problems
