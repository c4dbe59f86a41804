#include "kincal/framework/least_squares/least_squares_problem.hpp"

#include "kincal/framework/base/parallel.hpp"

#include <algorithm>
#include <limits>
#include <thread>

namespace kincal {

std::vector<std::string> LeastSquaresProblem::parameter_names() const {
  std::vector<std::string> names;
  for (int i = 0; i < num_parameters(); ++i) names.push_back("x" + std::to_string(i));
  return names;
}

namespace {

// Below this many blocks a thread costs more than it saves.
constexpr int kMinBlocksPerThread = 256;

}  // namespace

bool LeastSquaresProblem::evaluate_block_warm(int block, const VectorXd& x,
                                              Eigen::Ref<VectorXd> residuals,
                                              Eigen::Ref<MatrixXd>* jacobian, std::string* why,
                                              WarmStart&) const {
  return evaluate_block(block, x, residuals, jacobian, why);
}

bool LeastSquaresProblem::evaluate(const VectorXd& x, VectorXd* residuals, MatrixXd* jacobian,
                                   std::string* why, int num_threads, WarmStart* warm) const {
  const int blocks = num_residual_blocks();
  const int k = residuals_per_block();
  const int n = num_parameters();
  VectorXd local_residuals;
  VectorXd& r = residuals ? *residuals : local_residuals;
  r.resize(blocks * k);
  if (jacobian) jacobian->resize(blocks * k, n);

  auto run_range = [&](int begin, int end, std::string* reason) {
    // With no parameters the Jacobian has no storage, and a block of it would offset a null
    // pointer (undefined behaviour, found by UBSan): each block gets an empty k x 0 matrix.
    MatrixXd no_columns(k, 0);
    auto block = [&](int b, Eigen::Ref<MatrixXd>* rows) {
      return warm ? evaluate_block_warm(b, x, r.segment(b * k, k), rows, reason, *warm)
                  : evaluate_block(b, x, r.segment(b * k, k), rows, reason);
    };
    for (int b = begin; b < end; ++b) {
      bool ok;
      if (jacobian && n == 0) {
        Eigen::Ref<MatrixXd> rows(no_columns);
        ok = block(b, &rows);
      } else if (jacobian) {
        Eigen::Ref<MatrixXd> rows = jacobian->middleRows(b * k, k);
        ok = block(b, &rows);
      } else {
        ok = block(b, nullptr);
      }
      if (!ok) return false;
    }
    return true;
  };

  const int wanted = num_threads > 0 ? num_threads : hardware_threads();
  const int threads = std::max(1, std::min(wanted, blocks / kMinBlocksPerThread));
  if (threads <= 1) return run_range(0, blocks, why);

  // Contiguous chunks, one per thread; the first failure (lowest block) is reported.
  std::vector<std::thread> pool;
  std::vector<std::string> reasons(threads);
  std::vector<char> ok(threads, 1);
  const int chunk = (blocks + threads - 1) / threads;
  for (int t = 0; t < threads; ++t) {
    const int begin = t * chunk, end = std::min(blocks, begin + chunk);
    pool.emplace_back([&, t, begin, end] { ok[t] = run_range(begin, end, &reasons[t]); });
  }
  for (auto& th : pool) th.join();
  for (int t = 0; t < threads; ++t) {
    if (!ok[t]) {
      if (why) *why = reasons[t];
      return false;
    }
  }
  return true;
}

double LeastSquaresProblem::cost(const VectorXd& x, std::string* why) const {
  VectorXd r;
  if (!evaluate(x, &r, nullptr, why)) return std::numeric_limits<double>::infinity();
  return 0.5 * r.squaredNorm();
}

}  // namespace kincal
