// The triangular factor of a tall matrix, formed block by block, against Eigen's decompositions
// of the whole matrix: what the identifiability analysis, the covariance and the stationarity
// measure take from it (A^T A, singular values, least-squares solutions) must not change. And
// the other tall-matrix helpers of large calibrations: B^T B on all cores, fixed chunks.

#include "kincal/framework/base/triangular_factor.hpp"

#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <algorithm>
#include <vector>

#include "kincal/framework/base/gram_matrix.hpp"
#include "kincal/framework/base/parallel.hpp"
#include "kincal/framework/base/random.hpp"

namespace kincal {
namespace {

MatrixXd random_matrix(Random& rng, int rows, int cols) {
  MatrixXd a(rows, cols);
  for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] = rng.symmetric(1.0);
  return a;
}

TEST(TriangularFactor, KeepsTheGramMatrixAndTheSingularValues) {
  Random rng(3);
  // Fewer rows than one block, exactly one, and several blocks with a short last one.
  for (const int rows : {40, 1024, 2500}) {
    MatrixXd A = random_matrix(rng, rows, 7);
    A.col(3) *= 1e-6;  // ill-conditioned, as calibration Jacobians are
    const MatrixXd R = triangular_factor(A);
    ASSERT_EQ(R.rows(), 7);
    EXPECT_TRUE(R.isUpperTriangular(0.0)) << rows;
    const MatrixXd gram = A.transpose() * A;
    EXPECT_LT((R.transpose() * R - gram).norm(), 1e-12 * gram.norm()) << rows;
    const VectorXd s = Eigen::JacobiSVD<MatrixXd>(A).singularValues();
    const VectorXd s_R = Eigen::JacobiSVD<MatrixXd>(R).singularValues();
    EXPECT_LT((s - s_R).cwiseQuotient(s).cwiseAbs().maxCoeff(), 1e-10) << rows;
  }
}

TEST(TriangularFactor, RowsAddedInPiecesGiveTheSameFactor) {
  Random rng(5);
  const MatrixXd A = random_matrix(rng, 300, 5);
  TriangularFactor pieces(5, 64);
  pieces.add_rows(A.topRows(1));
  pieces.add_rows(A.middleRows(1, 150));
  pieces.add_rows(A.bottomRows(149));
  const MatrixXd whole = triangular_factor(A);
  // Unique up to the signs of the rows.
  for (int i = 0; i < 5; ++i) {
    const double sign = whole(i, i) * pieces.R()(i, i) < 0 ? -1.0 : 1.0;
    EXPECT_LT((sign * pieces.R().row(i) - whole.row(i)).norm(), 1e-12 * whole.norm()) << i;
  }
  pieces.reset();
  pieces.add_rows(A);
  EXPECT_LT((pieces.R().transpose() * pieces.R() - A.transpose() * A).norm(), 1e-11);
}

TEST(TriangularFactor, AZeroColumnStaysExactlyZero) {
  Random rng(7);
  MatrixXd A = random_matrix(rng, 2000, 6);
  A.col(2).setZero();
  const MatrixXd R = triangular_factor(A);
  EXPECT_TRUE(R.col(2).isZero(0.0));
}

TEST(TriangularFactor, SolvesLeastSquaresThroughTheAugmentedFactor) {
  // The factor of [A b]: its leading block is A's R and its last column's head is Q^T b, so
  // R y = Q^T b is the least-squares solution of A y = b (the stationarity measure's use).
  Random rng(9);
  const MatrixXd A = random_matrix(rng, 3000, 4);
  const VectorXd b = random_matrix(rng, 3000, 1).col(0);
  MatrixXd augmented(3000, 5);
  augmented << A, b;
  const MatrixXd F = triangular_factor(augmented);
  const VectorXd y = F.topLeftCorner(4, 4).triangularView<Eigen::Upper>().solve(F.col(4).head(4));
  const VectorXd expected = A.colPivHouseholderQr().solve(b);
  EXPECT_LT((y - expected).norm(), 1e-12 * expected.norm());
  // |A y - b| is the factor's last diagonal entry.
  EXPECT_NEAR(std::abs(F(4, 4)), (A * y - b).norm(), 1e-10);
}

TEST(TriangularFactor, ALargeMatrixSplitOverCoresGivesTheSameGramMatrix) {
  // From 131072 rows on, chunks of 65536 rows are factored on all cores and stacked in order.
  Random rng(17);
  const MatrixXd A = random_matrix(rng, 300000, 6);
  const MatrixXd R = triangular_factor(A);
  EXPECT_TRUE(R.isUpperTriangular(0.0));
  const MatrixXd gram = A.transpose() * A;
  EXPECT_LT((R.transpose() * R - gram).norm(), 1e-12 * gram.norm());
  TriangularFactor serial(6);
  serial.add_rows(A);
  for (int i = 0; i < 6; ++i)  // the same factor, up to the signs of its rows
    EXPECT_NEAR(std::abs(R(i, i)), std::abs(serial.R()(i, i)), 1e-10 * std::abs(R(i, i))) << i;
}

// The factor of [A B] without forming it: every inner product of the two sets of columns
// (what the identifiability analysis needs of J and the measurement frame's turns), on one
// core and split over chunks, and [A B] itself when it is not tall.
TEST(TriangularFactor, OfTwoMatricesSideBySideKeepsEveryInnerProduct) {
  Random rng(13);
  for (const int rows : {6, 2500, 140000}) {
    const MatrixXd A = random_matrix(rng, rows, 5), B = random_matrix(rng, rows, 2);
    MatrixXd both(rows, 7);
    both << A, B;
    const MatrixXd R = triangular_factor(A, B);
    const MatrixXd gram = both.transpose() * both;
    if (rows <= 7) {
      EXPECT_EQ(R, both);
      continue;
    }
    ASSERT_EQ(R.rows(), 7);
    EXPECT_TRUE(R.isUpperTriangular(0.0)) << rows;
    EXPECT_LT((R.transpose() * R - gram).norm(), 1e-12 * gram.norm()) << rows;
    // Nothing on the right: the factor of A alone, to the last bit.
    EXPECT_EQ(triangular_factor(A, MatrixXd(rows, 0)), triangular_factor(A)) << rows;
  }
  EXPECT_THROW(triangular_factor(MatrixXd::Ones(10, 2), MatrixXd::Ones(9, 1)),
               std::invalid_argument);
}

TEST(GramMatrix, IsBTransposeBOnSmallAndOnLargeMatrices) {
  Random rng(19);
  for (const int rows : {50, 300000}) {  // one rank update; chunks on all cores
    const MatrixXd B = random_matrix(rng, rows, 5);
    MatrixXd H = MatrixXd::Constant(5, 5, 7.0);  // whatever was there is replaced
    gram_lower(B, H);
    const MatrixXd expected = B.transpose() * B;
    EXPECT_LT((H.triangularView<Eigen::Lower>().toDenseMatrix() -
               expected.triangularView<Eigen::Lower>().toDenseMatrix())
                  .norm(),
              1e-12 * expected.norm())
        << rows;
    EXPECT_TRUE(H.triangularView<Eigen::StrictlyUpper>().toDenseMatrix().isZero(0.0)) << rows;
  }
}

TEST(ParallelChunks, VisitsEveryItemOnceInFixedChunks) {
  for (const int count : {0, 1, 999, 1000, 1001, 123457}) {
    std::vector<int> visits(static_cast<std::size_t>(count), 0);
    std::vector<int> chunk_begin(static_cast<std::size_t>(chunk_count(count, 1000)), -1);
    parallel_chunks(count, 1000, [&](int chunk, int begin, int end) {
      chunk_begin[static_cast<std::size_t>(chunk)] = begin;
      EXPECT_EQ(end, std::min(count, begin + 1000));
      for (int i = begin; i < end; ++i) ++visits[static_cast<std::size_t>(i)];
    });
    for (int v : visits) ASSERT_EQ(v, 1) << count;
    for (std::size_t c = 0; c < chunk_begin.size(); ++c)
      EXPECT_EQ(chunk_begin[c], static_cast<int>(c) * 1000) << count;
  }
}

TEST(TriangularFactor, AMatrixWithNoMoreRowsThanColumnsIsReturnedAsItIs) {
  Random rng(13);
  const MatrixXd A = random_matrix(rng, 3, 5);
  EXPECT_EQ(triangular_factor(A), A);
}

}  // namespace
}  // namespace kincal
