// The fixed-size 6 x 6 LU of forward kinematics against Eigen's, on random and on
// pivot-hungry matrices.

#include "kincal/framework/base/lu6.hpp"

#include <gtest/gtest.h>

#include "kincal/framework/base/random.hpp"

namespace kincal {
namespace {

Matrix6d random_matrix(Random& rng) {
  Matrix6d a;
  for (int i = 0; i < 36; ++i) a.data()[i] = rng.symmetric(1.0);
  return a;
}

Vector6d random_vector(Random& rng) {
  Vector6d v;
  for (int i = 0; i < 6; ++i) v[i] = rng.symmetric(1.0);
  return v;
}

TEST(Lu6, SolvesLikeEigen) {
  Random rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    Matrix6d a = random_matrix(rng);
    if (trial % 2) {
      // Zeros on the diagonal and a permuted identity part force every row swap.
      a.diagonal().setZero();
      a.col(trial % 6) *= 1e-3;
    }
    const Vector6d b = random_vector(rng);
    const Lu6 lu(a);
    const Eigen::PartialPivLU<Matrix6d> reference(a);
    const double scale = 1.0 + reference.solve(b).norm();
    EXPECT_LT((lu.solve(b) - reference.solve(b)).norm(), 1e-10 * scale) << "trial " << trial;
    EXPECT_LT((a * lu.solve(b) - b).norm(), 1e-12 * (1.0 + a.norm() * scale)) << "trial " << trial;
    EXPECT_LT((a.transpose() * lu.solve_transposed(b) - b).norm(),
              1e-12 * (1.0 + a.norm() * (1.0 + lu.solve_transposed(b).norm())))
        << "trial " << trial;
    EXPECT_LT((a * lu.inverse() - Matrix6d::Identity()).norm(), 1e-10 * (1.0 + a.norm()))
        << "trial " << trial;
    EXPECT_FALSE(lu.near_singular(a)) << "trial " << trial;
  }
}

// Textbook partial pivoting: the first row of largest |entry| becomes the pivot and trades
// places with row K. Lu6 must choose the same pivots, so that its solves are those of this
// loop to the last bit, ties included.
Vector6d textbook_solve(Matrix6d a, Vector6d b) {
  for (int k = 0; k < 6; ++k) {
    int pivot = k;
    for (int i = k + 1; i < 6; ++i)
      if (std::abs(a(i, k)) > std::abs(a(pivot, k))) pivot = i;
    a.row(k).swap(a.row(pivot));
    std::swap(b[k], b[pivot]);
    const double inverse_pivot = 1.0 / a(k, k);
    for (int i = k + 1; i < 6; ++i) {
      const double f = a(i, k) *= inverse_pivot;
      for (int j = k + 1; j < 6; ++j) a(i, j) -= f * a(k, j);
    }
  }
  Vector6d y = b, x;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < i; ++j) y[i] -= a(i, j) * y[j];
  for (int i = 5; i >= 0; --i) {
    double sum = y[i];
    for (int j = i + 1; j < 6; ++j) sum -= a(i, j) * x[j];
    x[i] = sum * (1.0 / a(i, i));
  }
  return x;
}

TEST(Lu6, ChoosesTheTextbookPivotsOnTies) {
  // Small integers: many columns hold equal |entries|, as the symmetric poses of a designed
  // experiment do. A different pivot on a tie changes the solve's rounding.
  Random rng(13);
  int compared = 0;
  for (int trial = 0; trial < 500; ++trial) {
    Matrix6d a;
    for (int i = 0; i < 36; ++i) a.data()[i] = std::round(rng.symmetric(2.5)) + 0.1 * (i % 3);
    const Vector6d b = random_vector(rng);
    const Lu6 lu(a);
    if (lu.near_singular(a)) continue;
    ++compared;
    const Vector6d x = lu.solve(b), expected = textbook_solve(a, b);
    for (int i = 0; i < 6; ++i)
      EXPECT_EQ(x[i], expected[i]) << "trial " << trial << ", entry " << i;
  }
  EXPECT_GT(compared, 400);
}

TEST(Lu6, FlagsSingularMatrices) {
  Random rng(12);
  Matrix6d a = random_matrix(rng);
  a.row(4) = 2.0 * a.row(1) - a.row(3);  // rank 5
  EXPECT_TRUE(Lu6(a).near_singular(a));
  Matrix6d zero_column = random_matrix(rng);
  zero_column.col(2).setZero();
  EXPECT_TRUE(Lu6(zero_column).near_singular(zero_column));
  EXPECT_TRUE(Lu6(Matrix6d::Zero()).near_singular(Matrix6d::Zero()));
}

}  // namespace
}  // namespace kincal
