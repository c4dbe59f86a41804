#pragma once
// The triangular factor of a tall matrix, for the SVDs and least-squares solves on calibration
// Jacobians: with A = Q R, R^T R = A^T A, so R has A's singular values, right singular vectors
// and column norms, and min |A y - b| is min |R y - Q^T b| (the last column of the factor of
// [A b] holds Q^T b). Formed over blocks of rows, it needs memory for about n^2 numbers
// however many rows A has: at 10^6 readings and 24 parameters, kilobytes instead of the
// 192 MB copies of A (and an SVD's own) that made the analyses of a large calibration need
// more memory than its solve.

#include "kincal/framework/base/types.hpp"

#include <Eigen/QR>

namespace kincal {

/// Accumulates R over blocks of rows: after add_rows(A_1), ..., add_rows(A_k), R() is a
/// triangular factor of [A_1; ...; A_k] (up to the signs of its rows). Each block is one
/// Householder QR of [R so far; the block], of a fixed size, so once constructed nothing is
/// allocated.
class TriangularFactor {
 public:
  /// For matrices of `cols` columns, taking `rows_per_block` rows per QR (at most 1024).
  explicit TriangularFactor(Eigen::Index cols, Eigen::Index rows_per_block = 1024);
  /// Back to no rows; keeps the storage.
  void reset() { R_.setZero(); }
  /// Adds rows (any number).
  void add_rows(const Eigen::Ref<const MatrixXd>& rows);
  /// The cols x cols upper-triangular factor of the rows added so far.
  const MatrixXd& R() const { return R_; }

 private:
  MatrixXd R_, stacked_;
  Eigen::HouseholderQR<MatrixXd> qr_;
};

/// The n x n triangular factor of an m x n A with m > n (a zero column of A stays exactly
/// zero); A itself when it has no more rows than columns.
MatrixXd triangular_factor(const Eigen::Ref<const MatrixXd>& A);

/// The (n + k) x (n + k) triangular factor of [A B] (A m x n, B m x k, the same rows), formed
/// without copying them side by side; [A B] itself when m <= n + k. Its first n columns are a
/// factor of A, and the pair keeps every inner product between A's and B's columns: what an
/// analysis of A's columns together with directions B needs (identifiability.hpp).
MatrixXd triangular_factor(const Eigen::Ref<const MatrixXd>& A,
                           const Eigen::Ref<const MatrixXd>& B);

}  // namespace kincal
