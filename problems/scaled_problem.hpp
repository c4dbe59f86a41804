#pragma once
// The same least-squares problem with every residual multiplied by one constant: what a model's
// reading_std common to every reading, a unit of the readings or a robust loss's scale does to
// a calibration. The minimiser does not move, so no backend's result may (docs/solvers.md,
// "Scale"): the tests solve through this to hold every backend to that.

#include "kincal/framework/least_squares/least_squares_problem.hpp"

namespace kincal::problems {

class ScaledProblem final : public LeastSquaresProblem {
 public:
  /// `scale` must be finite and non-zero; `inner` must outlive this.
  ScaledProblem(const LeastSquaresProblem& inner, double scale);

  int num_parameters() const override { return inner_.num_parameters(); }
  int num_residual_blocks() const override { return inner_.num_residual_blocks(); }
  int residuals_per_block() const override { return inner_.residuals_per_block(); }
  std::vector<std::string> parameter_names() const override { return inner_.parameter_names(); }
  bool evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                      Eigen::Ref<MatrixXd>* jacobian, std::string* why) const override;
  /// The inner problem's warm starts, passed on (lm solves it as it solves the inner one).
  std::unique_ptr<WarmStart> make_warm_start() const override { return inner_.make_warm_start(); }
  bool evaluate_block_warm(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                           Eigen::Ref<MatrixXd>* jacobian, std::string* why,
                           WarmStart& warm) const override;
  double scale() const { return scale_; }

 private:
  bool scaled(bool ok, Eigen::Ref<VectorXd> residuals, Eigen::Ref<MatrixXd>* jacobian) const;
  const LeastSquaresProblem& inner_;
  double scale_;
};

}  // namespace kincal::problems
