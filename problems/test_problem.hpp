#pragma once
// A test problem of a published collection: a LeastSquaresProblem with an analytic Jacobian,
// its standard starting point, and what the publication says about its minima.
//
// Costs follow kincal's convention, cost = 1/2 |r|^2. Moré, Garbow and Hillstrom publish
// f = |r|^2 = sum r_i^2, so every published value here is half the paper's.

#include <optional>
#include <string>
#include <vector>

#include "kincal/framework/least_squares/least_squares_problem.hpp"

namespace kincal::problems {

/// One minimum the publication reports.
struct PublishedMinimum {
  double cost = 0;         ///< 1/2 |r|^2 (half the published f)
  std::vector<double> x;   ///< a minimiser, when the publication gives a finite one
  bool x_is_exact = true;  ///< false when the publication prints it to a few digits only
  bool global = true;      ///< the lowest value the publication reports for this size
  std::string where;       ///< how the publication describes it, e.g. "at (0.8406, -inf, -inf)"
};

/// A problem with all its residuals in one block (m residuals, n parameters). Residuals or
/// Jacobian entries that are not finite, and costs that overflow, make the evaluation fail
/// with the reason, as forward kinematics failing does for a calibration.
class TestProblem : public LeastSquaresProblem {
 public:
  TestProblem(std::string name, std::string title, int number, int n, int m, VectorXd start);

  /// Short identifier, e.g. "mgh20_watson_n9"; unique within a collection.
  const std::string& name() const { return name_; }
  /// The publication's title, e.g. "Watson function".
  const std::string& title() const { return title_; }
  /// The problem's number in the publication (MGH: 1-35).
  int number() const { return number_; }
  /// The standard starting point x0.
  const VectorXd& start() const { return start_; }
  /// Published minima for this size, the global one first.
  const std::vector<PublishedMinimum>& minima() const { return minima_; }
  /// The lowest published cost (1/2 |r|^2).
  double published_minimum() const { return minima_.front().cost; }
  /// Source and caveats, one line.
  const std::string& note() const { return note_; }

  int num_parameters() const override { return n_; }
  int num_residual_blocks() const override { return 1; }
  int residuals_per_block() const override { return m_; }
  bool evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                      Eigen::Ref<MatrixXd>* jacobian, std::string* why) const override;

 protected:
  /// All m residuals and, when `jacobian` is non-null, the m x n Jacobian (pre-sized). Returns
  /// false with a reason where the formula is undefined (e.g. a division by zero).
  virtual bool compute(const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* jacobian,
                       std::string* why) const = 0;

  void add_minimum(PublishedMinimum minimum) { minima_.push_back(std::move(minimum)); }
  void set_note(std::string note) { note_ = std::move(note); }

 private:
  std::string name_, title_;
  int number_, n_, m_;
  VectorXd start_;
  std::vector<PublishedMinimum> minima_;
  std::string note_;
};

}  // namespace kincal::problems
