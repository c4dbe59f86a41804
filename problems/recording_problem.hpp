#pragma once
// A LeastSquaresProblem that forwards to another and remembers every point evaluated at, with
// its cost when every residual block could be computed there, with finite values (and a finite
// Jacobian, where one was asked for): what the contract checker uses to know the best point a
// backend ever saw.

#include <map>
#include <mutex>
#include <vector>

#include "kincal/framework/least_squares/least_squares_problem.hpp"

namespace kincal::problems {

class RecordingProblem final : public LeastSquaresProblem {
 public:
  explicit RecordingProblem(const LeastSquaresProblem& inner) : inner_(inner) {}

  int num_parameters() const override { return inner_.num_parameters(); }
  int num_residual_blocks() const override { return inner_.num_residual_blocks(); }
  int residuals_per_block() const override { return inner_.residuals_per_block(); }
  std::vector<std::string> parameter_names() const override { return inner_.parameter_names(); }
  bool evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                      Eigen::Ref<MatrixXd>* jacobian, std::string* why) const override;
  /// The inner problem's warm starts, passed on: the backend under check solves as it would
  /// solve the inner problem itself (lm's forward kinematics from the last poses), rounding
  /// included.
  std::unique_ptr<WarmStart> make_warm_start() const override { return inner_.make_warm_start(); }
  bool evaluate_block_warm(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                           Eigen::Ref<MatrixXd>* jacobian, std::string* why,
                           WarmStart& warm) const override;

  /// Distinct points with every block computed, and the lowest cost among them (the sum is
  /// ours, block by block, so it may differ from a backend's by rounding).
  int complete_points() const;
  double best_cost() const;
  VectorXd best_point() const;
  /// Calls to evaluate_block.
  long block_evaluations() const;

 private:
  bool record(int block, const VectorXd& x, bool ok, const Eigen::Ref<VectorXd>& residuals,
              const Eigen::Ref<MatrixXd>* jacobian) const;

  struct Point {
    std::vector<char> done;  // per block
    int blocks_done = 0;
    double sum = 0;  // of squared residuals over the blocks done
    bool failed = false;
  };
  const LeastSquaresProblem& inner_;
  mutable std::mutex mutex_;
  mutable std::map<std::vector<double>, Point> points_;
  mutable long block_evaluations_ = 0;
};

}  // namespace kincal::problems
