#pragma once
// LU factorisation of a small fixed-size square matrix, for closed-chain kinematics: the
// unrolled Lu6 for 6 x 6 (the hexapod's kernel), Eigen's fixed-size PartialPivLU otherwise.
// No allocation for fixed sizes.

#include <Eigen/LU>

#include "kincal/framework/base/lu6.hpp"

namespace kincal {

template <int N>
class SmallLu {
 public:
  using Matrix = Eigen::Matrix<double, N, N>;
  using Vector = Eigen::Matrix<double, N, 1>;

  explicit SmallLu(const Matrix& a) : lu_(a) {}

  Vector solve(const Vector& b) const { return lu_.solve(b); }
  /// x with A^T x = b.
  Vector solve_transposed(const Vector& b) const { return lu_.transpose().solve(b); }
  Matrix inverse() const { return lu_.inverse(); }
  /// A tiny reciprocal condition number (Eigen's L1 estimate below 1e-12).
  bool near_singular(const Matrix&) const {
    return !(std::abs(lu_.determinant()) > 1e-300) || lu_.rcond() < 1e-12;
  }

 private:
  Eigen::PartialPivLU<Matrix> lu_;
};

template <>
class SmallLu<6> : public Lu6 {
 public:
  using Lu6::Lu6;
};

}  // namespace kincal
