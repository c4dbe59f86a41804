#include "kincal/framework/base/lu6.hpp"

namespace kincal {

namespace {

using Rows = double[6][6];

// Column K of the elimination; the recursion unrolls the outer loop. The pivot is the first
// row of largest |entry| in column K, and it trades places with row K, as in the textbook
// loop; but both the search and the swap are written as selects at constant indices, so no
// branch depends on the data and the matrix can stay in registers: with a branch per
// comparison the search mispredicted, and a swap at a run-time index kept the matrix in
// memory. (Swapping row K with every larger row as the search goes would be simpler, but it
// leaves the other rows in another order, and on exact ties, as at the symmetric poses of a
// designed experiment, a later column would then choose another pivot.)
// This file is compiled without auto-vectorisation (CMakeLists.txt): the elimination is a
// chain of dependent scalar operations, and the vectorised code's 16-byte loads of entries
// just stored 8 bytes at a time stalled on store forwarding (docs/benchmarks.md).
template <int K>
void eliminate(Rows& m, int (&perm)[6], double (&inverse_pivots)[6]) {
  if constexpr (K < 6) {
    int pivot = K;
    double largest = std::abs(m[K][K]);
    for (int i = K + 1; i < 6; ++i) {
      const double candidate = std::abs(m[i][K]);
      const bool larger = candidate > largest;
      pivot = larger ? i : pivot;
      largest = larger ? candidate : largest;
    }
    for (int i = K + 1; i < 6; ++i) {
      const bool swap = i == pivot;
      for (int j = 0; j < 6; ++j) {
        const double upper = m[K][j], lower = m[i][j];
        m[K][j] = swap ? lower : upper;
        m[i][j] = swap ? upper : lower;
      }
      const int upper = perm[K], lower = perm[i];
      perm[K] = swap ? lower : upper;
      perm[i] = swap ? upper : lower;
    }
    inverse_pivots[K] = 1.0 / m[K][K];
    if (m[K][K] != 0.0) {  // singular: near_singular() says so
      for (int i = K + 1; i < 6; ++i) {
        const double f = m[i][K] *= inverse_pivots[K];
        for (int j = K + 1; j < 6; ++j) m[i][j] -= f * m[K][j];
      }
    }
    eliminate<K + 1>(m, perm, inverse_pivots);
  }
}

}  // namespace

Lu6::Lu6(const Matrix6d& a) {
  for (int r = 0; r < 6; ++r) {
    perm_[r] = r;
    for (int c = 0; c < 6; ++c) lu_[r][c] = a(r, c);
  }
  eliminate<0>(lu_, perm_, inverse_pivots_);
}

Vector6d Lu6::solve(const Vector6d& b) const {
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

// A^T = U^T L^T P: solve U^T z = b, then L^T w = z, then x = P^T w.
Vector6d Lu6::solve_transposed(const Vector6d& b) const {
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

Matrix6d Lu6::inverse() const {
  Matrix6d inv;
  for (int c = 0; c < 6; ++c) inv.col(c) = solve(Vector6d::Unit(c));
  return inv;
}

}  // namespace kincal
