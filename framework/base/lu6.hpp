#pragma once
// LU factorisation with partial pivoting of a 6 x 6 matrix, for the Newton steps of forward
// kinematics and the pose Jacobians: the innermost kernel of every calibration.
//
// Eigen's PartialPivLU<Matrix6d> runs its generic blocked code even at 6 x 6. Here the
// elimination is unrolled at compile time (one template instance per column), so every
// inner loop has a constant trip count and the whole factorisation is straight-line code
// on a plain row-major array. No allocation. Measured in docs/benchmarks.md.

#include <Eigen/LU>
#include <cmath>
#include <utility>

#include "kincal/framework/base/types.hpp"

namespace kincal {

class Lu6 {
 public:
  explicit Lu6(const Matrix6d& a) {
    for (int r = 0; r < 6; ++r) {
      perm_[r] = r;
      for (int c = 0; c < 6; ++c) lu_[r][c] = a(r, c);
    }
    eliminate<0>();
  }

  /// x with A x = b.
  Vector6d solve(const Vector6d& b) const {
    double y[6];
    for (int i = 0; i < 6; ++i) {
      double sum = b[perm_[i]];
      for (int j = 0; j < i; ++j) sum -= lu_[i][j] * y[j];
      y[i] = sum;
    }
    Vector6d x;
    for (int i = 5; i >= 0; --i) {
      double sum = y[i];
      for (int j = i + 1; j < 6; ++j) sum -= lu_[i][j] * x[j];
      x[i] = sum * inverse_pivots_[i];
    }
    return x;
  }

  /// x with A^T x = b: A^T = U^T L^T P, so solve U^T z = b, then L^T w = z, then x = P^T w.
  Vector6d solve_transposed(const Vector6d& b) const {
    double z[6];
    for (int i = 0; i < 6; ++i) {
      double sum = b[i];
      for (int j = 0; j < i; ++j) sum -= lu_[j][i] * z[j];
      z[i] = sum * inverse_pivots_[i];
    }
    for (int i = 5; i >= 0; --i)
      for (int j = i + 1; j < 6; ++j) z[i] -= lu_[j][i] * z[j];
    Vector6d x;
    for (int i = 0; i < 6; ++i) x[perm_[i]] = z[i];
    return x;
  }

  Matrix6d inverse() const {
    Matrix6d inv;
    for (int c = 0; c < 6; ++c) inv.col(c) = solve(Vector6d::Unit(c));
    return inv;
  }

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
  // Column K of the elimination; the recursion unrolls the outer loop.
  template <int K>
  void eliminate() {
    if constexpr (K < 6) {
      int p = K;
      double largest = std::abs(lu_[K][K]);
      for (int i = K + 1; i < 6; ++i) {
        const double v = std::abs(lu_[i][K]);
        if (v > largest) {
          largest = v;
          p = i;
        }
      }
      if (p != K) {
        for (int j = 0; j < 6; ++j) std::swap(lu_[K][j], lu_[p][j]);
        std::swap(perm_[K], perm_[p]);
      }
      inverse_pivots_[K] = 1.0 / lu_[K][K];
      if (lu_[K][K] != 0.0) {  // singular: near_singular() says so
        for (int i = K + 1; i < 6; ++i) {
          const double f = lu_[i][K] *= inverse_pivots_[K];
          for (int j = K + 1; j < 6; ++j) lu_[i][j] -= f * lu_[K][j];
        }
      }
      eliminate<K + 1>();
    }
  }

  double lu_[6][6];  // row-major: L below the diagonal (unit diagonal implied), U on and above
  double inverse_pivots_[6];
  int perm_[6];  // row i of LU is row perm_[i] of A
};

}  // namespace kincal
