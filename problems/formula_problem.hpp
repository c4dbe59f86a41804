#pragma once
// A TestProblem whose residuals and Jacobian are given by one function: how the collection's
// problems are written (problems/mgh_*.cpp), and a quick way to add one of your own.

#include <functional>
#include <memory>

#include "kincal/problems/test_problem.hpp"

namespace kincal::problems {

/// Fills the m residuals and, when the pointer is non-null, the Jacobian (zeroed beforehand,
/// so only the non-zero entries need writing). Returns false with a reason in `why` where the
/// formula is undefined.
using ResidualFunction = std::function<bool(const VectorXd& x, Eigen::Ref<VectorXd> r,
                                            Eigen::Ref<MatrixXd>* jacobian, std::string* why)>;

struct ProblemSpec {
  std::string name;   ///< e.g. "mgh01_rosenbrock"
  std::string title;  ///< e.g. "Rosenbrock function"
  int number = 0;     ///< number in the publication
  int n = 0, m = 0;
  VectorXd start;
  ResidualFunction residuals;
  std::vector<PublishedMinimum> minima;  ///< the global one first
  std::string note;
};

std::shared_ptr<const TestProblem> make_problem(ProblemSpec spec);

}  // namespace kincal::problems
