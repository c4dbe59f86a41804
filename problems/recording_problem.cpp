#include "kincal/problems/recording_problem.hpp"

#include <limits>

namespace kincal::problems {

bool RecordingProblem::evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                                      Eigen::Ref<MatrixXd>* jacobian, std::string* why) const {
  return record(block, x, inner_.evaluate_block(block, x, residuals, jacobian, why), residuals,
                jacobian);
}

bool RecordingProblem::evaluate_block_warm(int block, const VectorXd& x,
                                           Eigen::Ref<VectorXd> residuals,
                                           Eigen::Ref<MatrixXd>* jacobian, std::string* why,
                                           WarmStart& warm) const {
  return record(block, x, inner_.evaluate_block_warm(block, x, residuals, jacobian, why, warm),
                residuals, jacobian);
}

bool RecordingProblem::record(int block, const VectorXd& x, bool ok,
                              const Eigen::Ref<VectorXd>& residuals,
                              const Eigen::Ref<MatrixXd>* jacobian) const {
  std::lock_guard<std::mutex> lock(mutex_);
  ++block_evaluations_;
  Point& point = points_[std::vector<double>(x.data(), x.data() + x.size())];
  if (point.done.empty()) point.done.assign(static_cast<std::size_t>(num_residual_blocks()), 0);
  // A non-finite value fails the evaluation as much as a false return: no backend can use it
  // (a point whose Jacobian came out NaN is no point to return, whatever its cost).
  if (!ok || !residuals.allFinite() || (jacobian && !jacobian->allFinite())) {
    point.failed = true;
  } else if (!point.done[static_cast<std::size_t>(block)]) {
    point.done[static_cast<std::size_t>(block)] = 1;
    ++point.blocks_done;
    point.sum += residuals.squaredNorm();
  }
  return ok;
}

int RecordingProblem::complete_points() const {
  std::lock_guard<std::mutex> lock(mutex_);
  int count = 0;
  for (const auto& [x, point] : points_)
    count += !point.failed && point.blocks_done == num_residual_blocks();
  return count;
}

double RecordingProblem::best_cost() const {
  std::lock_guard<std::mutex> lock(mutex_);
  double best = std::numeric_limits<double>::infinity();
  for (const auto& [x, point] : points_)
    if (!point.failed && point.blocks_done == num_residual_blocks() && 0.5 * point.sum < best)
      best = 0.5 * point.sum;
  return best;
}

VectorXd RecordingProblem::best_point() const {
  std::lock_guard<std::mutex> lock(mutex_);
  double best = std::numeric_limits<double>::infinity();
  VectorXd at;
  for (const auto& [x, point] : points_)
    if (!point.failed && point.blocks_done == num_residual_blocks() && 0.5 * point.sum < best) {
      best = 0.5 * point.sum;
      at = Eigen::Map<const VectorXd>(x.data(), static_cast<Eigen::Index>(x.size()));
    }
  return at;
}

long RecordingProblem::block_evaluations() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return block_evaluations_;
}

}  // namespace kincal::problems
