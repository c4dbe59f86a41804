#pragma once
// A calibration problem with its model's parameter-only constraints
// (framework/kinematics/parameter_constraint.hpp) added once: residual_i / std_i after the data's
// residuals, so that minimising 1/2 |r|^2 minimises
//   1/2 |r_data(x)|^2 + 1/2 sum_i (c_i(x) / std_i)^2.
// Blocks stay uniform (LeastSquaresProblem's contract), as PriorProblem's: the data
// problem's blocks first, then ceil(c / k) blocks of k residuals (c the constraints'
// residuals, k the data problem's residuals_per_block), the last padded with zeros.
// solve_nested_calibration chains it with the prior, so every caller solves the same problem.

#include <functional>
#include <vector>

#include "kincal/framework/calibration/calibration_problem.hpp"
#include "kincal/framework/calibration/prior_problem.hpp"
#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

/// The whitened residuals (c_i / std_i) of every constraint of `problem`'s model at the free
/// parameters x, in constraint order, and when J is non-null their Jacobian in x (resized).
void constraint_residuals(const CalibrationProblem& problem, const VectorXd& x, VectorXd& residuals,
                          MatrixXd* J);
/// The number of constraint residuals of `model`.
int num_constraint_residuals(const MeasurementModel& model);
/// The constraints' rows appended below J (and their residuals below r, when non-null): the
/// data problem's Jacobian at x becomes the whole problem's, as identifiability and the
/// covariance must see it. No-op without constraints.
void append_constraint_rows(const CalibrationProblem& problem, const VectorXd& x, MatrixXd& J,
                            VectorXd* r = nullptr);

class ConstrainedProblem : public LeastSquaresProblem {
 public:
  /// `data` must outlive the wrapper.
  explicit ConstrainedProblem(const CalibrationProblem& data);

  int num_parameters() const override { return data_.num_parameters(); }
  int num_residual_blocks() const override { return data_blocks_ + constraint_blocks_; }
  int residuals_per_block() const override { return data_.residuals_per_block(); }
  std::vector<std::string> parameter_names() const override { return data_.parameter_names(); }

  bool evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                      Eigen::Ref<MatrixXd>* jacobian, std::string* why) const override;
  /// The data problem's warm start; its blocks are evaluated with it, the others as they are.
  std::unique_ptr<WarmStart> make_warm_start() const override { return data_.make_warm_start(); }
  bool evaluate_block_warm(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                           Eigen::Ref<MatrixXd>* jacobian, std::string* why,
                           WarmStart& warm) const override;

  /// The first data_problem().num_residuals() residuals are the data problem's, in its order.
  const CalibrationProblem& data_problem() const { return data_; }

 private:
  const CalibrationProblem& data_;
  int num_constraint_residuals_ = 0;
  int data_blocks_ = 0;
  int constraint_blocks_ = 0;
};

/// The problem solve_nested_calibration solves (with the model's constraints and `prior`, as
/// far as there are any), handed to `use` for as long as the call lasts.
void with_nested_problem(const CalibrationProblem& problem, const Prior& prior,
                         const std::function<void(const LeastSquaresProblem&)>& use);

/// Solves `problem` from x (in/out) in the nested formulation with its model's constraints,
/// when it has any, and with `prior`, when it has one: the problem every nested calibration
/// of such a model must solve. Callers use solve_calibration (calibration_solve.hpp), which
/// chooses the formulation.
Summary solve_nested_calibration(const Solver& solver, const CalibrationProblem& problem,
                                 const Prior& prior, VectorXd& x, const SolverOptions& options);

}  // namespace kincal
