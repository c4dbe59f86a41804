#include "kincal/problems/test_problem.hpp"

#include <cmath>
#include <stdexcept>

namespace kincal::problems {

TestProblem::TestProblem(std::string name, std::string title, int number, int n, int m,
                         VectorXd start)
    : name_(std::move(name)),
      title_(std::move(title)),
      number_(number),
      n_(n),
      m_(m),
      start_(std::move(start)) {
  if (start_.size() != n_ || m_ < 1)
    throw std::logic_error("test problem " + name_ + ": inconsistent sizes");
}

bool TestProblem::evaluate_block(int, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                                 Eigen::Ref<MatrixXd>* jacobian, std::string* why) const {
  if (!compute(x, residuals, jacobian, why)) return false;
  // Exponentials of large arguments overflow at the 10x and 100x starts of several problems;
  // such a point cannot be used in double precision, so it is reported like any point where
  // the residuals cannot be computed.
  for (int i = 0; i < m_; ++i) {
    if (!std::isfinite(residuals[i])) {
      if (why) *why = name_ + ": residual " + std::to_string(i) + " is not finite (overflow)";
      return false;
    }
  }
  if (!std::isfinite(0.5 * residuals.squaredNorm())) {
    if (why) *why = name_ + ": the cost 1/2 |r|^2 overflows";
    return false;
  }
  if (jacobian && !jacobian->allFinite()) {
    if (why) *why = name_ + ": the Jacobian is not finite (overflow)";
    return false;
  }
  return true;
}

}  // namespace kincal::problems
