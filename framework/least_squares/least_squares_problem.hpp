#pragma once
// A generic nonlinear least-squares problem, min_x 1/2 |r(x)|^2, that knows nothing of
// kinematics. Residuals come in equal-sized blocks (one block = one measured configuration)
// so that backends such as Ceres can see one residual block per measurement, and so that
// evaluation can be split across threads.

#include <string>
#include <vector>

#include "kincal/framework/base/types.hpp"

namespace kincal {

class LeastSquaresProblem {
 public:
  virtual ~LeastSquaresProblem() = default;

  virtual int num_parameters() const = 0;
  virtual int num_residual_blocks() const = 0;
  virtual int residuals_per_block() const = 0;
  int num_residuals() const { return num_residual_blocks() * residuals_per_block(); }

  /// Names for reports; default "x0", "x1", ...
  virtual std::vector<std::string> parameter_names() const;

  /// Residuals of one block and, when `jacobian` is non-null, its rows
  /// (residuals_per_block x num_parameters). Returns false, with a reason in `why` when
  /// non-null, when the residuals cannot be computed at x (e.g. forward kinematics failed).
  /// Must be safe to call concurrently from several threads.
  virtual bool evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                              Eigen::Ref<MatrixXd>* jacobian, std::string* why) const = 0;

  /// All residuals and, when `jacobian` is non-null, the full Jacobian. Sizes the outputs.
  /// Stops at the first failing block. Splits blocks over `num_threads` threads when the
  /// problem is large enough for that to pay.
  bool evaluate(const VectorXd& x, VectorXd* residuals, MatrixXd* jacobian,
                std::string* why = nullptr, int num_threads = 1) const;

  /// 1/2 |r(x)|^2, or +infinity when the residuals cannot be computed.
  double cost(const VectorXd& x, std::string* why = nullptr) const;
};

}  // namespace kincal
