#pragma once
// LU factorisation with partial pivoting of a 6 x 6 matrix, for the Newton steps of forward
// kinematics and the pose Jacobians: the innermost kernel of every calibration.
//
// Eigen's PartialPivLU<Matrix6d> runs its generic blocked code even at 6 x 6. Here the
// elimination is unrolled at compile time, and the pivot search and row swap are selects at
// constant indices, with no branch on the data: the factorisation and the solves (lu6.cpp)
// are straight-line scalar code, compiled without auto-vectorisation. They choose the
// textbook pivots, ties included. Measured in docs/benchmarks.md.

#include <Eigen/LU>
#include <cmath>

#include "kincal/framework/base/types.hpp"

namespace kincal {

class Lu6 {
 public:
  /// Factors `a`. A zero pivot leaves the columns after it unreduced; near_singular() says so.
  explicit Lu6(const Matrix6d& a);

  /// x with A x = b.
  Vector6d solve(const Vector6d& b) const;
  /// x with A^T x = b.
  Vector6d solve_transposed(const Vector6d& b) const;
  Matrix6d inverse() const;

  /// Whether `a`, the matrix factored, is singular: a tiny reciprocal condition number.
  /// Eigen's L1 rcond estimate costs several solves, a third of a forward kinematics solve
  /// when asked every iteration: it is only asked when the pivots already spread over four
  /// decades (cond(A) is at least max|u_ii| / min|u_ii|, and partial pivoting does not hide
  /// an rcond near 1e-12 behind well-spread pivots in the 6 x 6 Jacobians of real mechanisms).
  bool near_singular(const Matrix6d& a) const {
    double product = 1, smallest = std::abs(lu_[0][0]), largest = smallest;
    for (int i = 0; i < 6; ++i) {
      const double pivot = std::abs(lu_[i][i]);
      product *= pivot;
      smallest = std::min(smallest, pivot);
      largest = std::max(largest, pivot);
    }
    if (!(product > 1e-300)) return true;
    if (smallest > 1e-4 * largest) return false;
    return Eigen::PartialPivLU<Matrix6d>(a).rcond() < 1e-12;
  }

 private:
  double lu_[6][6];  // row-major: L below the diagonal (unit diagonal implied), U on and above
  double inverse_pivots_[6];
  int perm_[6];  // row i of LU is row perm_[i] of A
};

}  // namespace kincal
