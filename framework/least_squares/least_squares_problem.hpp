#pragma once
// A generic nonlinear least-squares problem, min_x 1/2 |r(x)|^2, that knows nothing of
// kinematics. Residuals come in equal-sized blocks (one block = one measured configuration)
// so that backends such as Ceres can see one residual block per measurement, and so that
// evaluation can be split across threads.

#include <memory>
#include <string>
#include <vector>

#include "kincal/framework/base/types.hpp"

namespace kincal {

/// What a problem carries from one evaluation to the next within one solve, so that an inner
/// iteration starts closer to its answer (a calibration problem keeps each configuration's
/// last pose, from which forward kinematics starts; docs/architecture.md, "Warm starts").
/// Made by LeastSquaresProblem::make_warm_start(), owned by one solve and passed to its
/// evaluations only, never shared by concurrent solves: evaluation stays thread-safe, and a
/// solve's result depends only on its own history. It may change residuals only at the
/// rounding level of the inner iteration.
class WarmStart {
 public:
  virtual ~WarmStart() = default;
};

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
  /// A warm start for one solve; null (the default) when evaluations have nothing to carry.
  virtual std::unique_ptr<WarmStart> make_warm_start() const { return nullptr; }
  /// evaluate_block with `warm`, which came from this problem's make_warm_start(); calls for
  /// different blocks may run concurrently. Default: evaluate_block.
  virtual bool evaluate_block_warm(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                                   Eigen::Ref<MatrixXd>* jacobian, std::string* why,
                                   WarmStart& warm) const;

  /// All residuals and, when `jacobian` is non-null, the full Jacobian. Sizes the outputs.
  /// Stops at the first failing block. Splits blocks over `num_threads` threads (0 = all
  /// cores) when each gets at least 256 of them; the result does not depend on the number.
  /// With `warm` (from make_warm_start(), or null), each block is evaluated warm.
  bool evaluate(const VectorXd& x, VectorXd* residuals, MatrixXd* jacobian,
                std::string* why = nullptr, int num_threads = 0, WarmStart* warm = nullptr) const;

  /// 1/2 |r(x)|^2, or +infinity when the residuals cannot be computed.
  double cost(const VectorXd& x, std::string* why = nullptr) const;
};

}  // namespace kincal
