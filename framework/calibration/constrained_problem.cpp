#include "kincal/framework/calibration/constrained_problem.hpp"

#include <cmath>

namespace kincal {

int num_constraint_residuals(const MeasurementModel& model) {
  int n = 0;
  for (const auto& c : model.constraints()) n += c->num_residuals();
  return n;
}

void constraint_residuals(const CalibrationProblem& problem, const VectorXd& x, VectorXd& residuals,
                          MatrixXd* J) {
  const MeasurementModel& model = problem.model();
  const VectorXd full = problem.full_parameters(x);
  // Where each model parameter sits among the free ones (-1: fixed).
  std::vector<int> free_position(model.num_parameters(), -1);
  for (std::size_t j = 0; j < problem.free_indices().size(); ++j)
    free_position[problem.free_indices()[j]] = static_cast<int>(j);
  residuals.resize(num_constraint_residuals(model));
  if (J) J->setZero(residuals.size(), problem.num_parameters());
  int row = 0;
  for (std::size_t k = 0; k < model.constraints().size(); ++k) {
    const ParameterConstraint& c = *model.constraints()[k];
    const std::vector<int>& indices = model.constraint_parameter_indices(static_cast<int>(k));
    const int n = c.num_residuals();
    VectorXd values(indices.size());
    for (std::size_t i = 0; i < indices.size(); ++i) values[static_cast<int>(i)] = full[indices[i]];
    VectorXd r(n);
    MatrixXd Jc(n, static_cast<int>(indices.size()));
    c.evaluate(values, r, J ? &Jc : nullptr);
    const VectorXd inverse_std = c.residual_std().cwiseInverse();
    residuals.segment(row, n) = inverse_std.asDiagonal() * r;
    if (J)
      for (std::size_t i = 0; i < indices.size(); ++i)
        if (free_position[indices[i]] >= 0)
          J->block(row, free_position[indices[i]], n, 1) +=
              inverse_std.asDiagonal() * Jc.col(static_cast<int>(i));
    row += n;
  }
}

void append_constraint_rows(const CalibrationProblem& problem, const VectorXd& x, MatrixXd& J,
                            VectorXd* r) {
  if (problem.model().constraints().empty()) return;
  VectorXd rc;
  MatrixXd Jc;
  constraint_residuals(problem, x, rc, &Jc);
  const Eigen::Index rows = J.rows();
  J.conservativeResize(rows + Jc.rows(), Eigen::NoChange);
  if (J.cols() > 0) J.bottomRows(Jc.rows()) = Jc;
  if (r) {
    r->conservativeResize(rows + rc.size());
    r->tail(rc.size()) = rc;
  }
}

ConstrainedProblem::ConstrainedProblem(const CalibrationProblem& data)
    : data_(data),
      num_constraint_residuals_(num_constraint_residuals(data.model())),
      data_blocks_(data.num_residual_blocks()) {
  const int k = data_.residuals_per_block();
  constraint_blocks_ = k > 0 ? (num_constraint_residuals_ + k - 1) / k : 0;
}

bool ConstrainedProblem::evaluate_block_warm(int block, const VectorXd& x,
                                             Eigen::Ref<VectorXd> residuals,
                                             Eigen::Ref<MatrixXd>* jacobian, std::string* why,
                                             WarmStart& warm) const {
  if (block < data_blocks_)
    return data_.evaluate_block_warm(block, x, residuals, jacobian, why, warm);
  return evaluate_block(block, x, residuals, jacobian, why);
}

bool ConstrainedProblem::evaluate_block(int block, const VectorXd& x,
                                        Eigen::Ref<VectorXd> residuals,
                                        Eigen::Ref<MatrixXd>* jacobian, std::string* why) const {
  if (block < data_blocks_) return data_.evaluate_block(block, x, residuals, jacobian, why);
  // Once per evaluation, not per configuration: the few allocations here do not count.
  VectorXd r;
  MatrixXd J;
  constraint_residuals(data_, x, r, jacobian ? &J : nullptr);
  if (!r.allFinite()) {
    if (why) *why = "a parameter constraint is not finite";
    return false;
  }
  const int k = residuals_per_block();
  const int first = (block - data_blocks_) * k;
  const int count = std::min(k, num_constraint_residuals_ - first);
  residuals.setZero();
  residuals.head(count) = r.segment(first, count);
  if (jacobian && jacobian->cols() > 0) {
    jacobian->setZero();
    jacobian->topRows(count) = J.middleRows(first, count);
  }
  return true;
}

void with_nested_problem(const CalibrationProblem& problem, const Prior& prior,
                         const std::function<void(const LeastSquaresProblem&)>& use) {
  if (problem.model().constraints().empty()) {
    if (prior.any())
      use(PriorProblem(problem, prior));
    else
      use(problem);
    return;
  }
  const ConstrainedProblem constrained(problem);
  if (prior.any())
    use(PriorProblem(constrained, prior));
  else
    use(constrained);
}

Summary solve_nested_calibration(const Solver& solver, const CalibrationProblem& problem,
                                 const Prior& prior, VectorXd& x, const SolverOptions& options) {
  Summary summary;
  with_nested_problem(problem, prior, [&](const LeastSquaresProblem& nested) {
    summary = solver.solve(nested, x, options);
  });
  return summary;
}

}  // namespace kincal
