#include "kincal/framework/base/triangular_factor.hpp"

#include <algorithm>
#include <climits>
#include <stdexcept>
#include <string>
#include <vector>

#include "kincal/framework/base/parallel.hpp"

namespace kincal {

namespace {

// Enough rows per QR that the n x n head stacked on each block is a small share of the work,
// few enough that the block stays in cache.
constexpr Eigen::Index kMaxRowsPerBlock = 1024;
// Rows per chunk when triangular_factor() splits a tall matrix over cores.
constexpr int kRowsPerChunk = 65536;

}  // namespace

TriangularFactor::TriangularFactor(Eigen::Index cols, Eigen::Index rows_per_block)
    : R_(MatrixXd::Zero(cols, cols)),
      stacked_(cols + std::clamp<Eigen::Index>(rows_per_block, 1, kMaxRowsPerBlock), cols),
      qr_(stacked_.rows(), cols) {}

void TriangularFactor::add_rows(const Eigen::Ref<const MatrixXd>& rows) {
  const Eigen::Index n = R_.cols(), block = stacked_.rows() - n;
  if (n == 0) return;
  for (Eigen::Index begin = 0; begin < rows.rows(); begin += block) {
    const Eigen::Index count = std::min(block, rows.rows() - begin);
    // A short block is padded with zero rows, which leave R as it is: the QR keeps one size.
    stacked_.topRows(n) = R_;
    stacked_.middleRows(n, count) = rows.middleRows(begin, count);
    stacked_.bottomRows(block - count).setZero();
    qr_.compute(stacked_);
    R_ = qr_.matrixQR().topRows(n).triangularView<Eigen::Upper>();
  }
}

namespace {

// The factor of the rows [begin, end) of [A B] (B may have no columns), in blocks of
// kMaxRowsPerBlock rows, so that [A B] is never formed whole.
MatrixXd factor_of_rows(const Eigen::Ref<const MatrixXd>& A, const Eigen::Ref<const MatrixXd>& B,
                        Eigen::Index begin, Eigen::Index end) {
  const Eigen::Index n = A.cols() + B.cols();
  TriangularFactor factor(n, std::min(end - begin, kMaxRowsPerBlock));
  if (B.cols() == 0) {
    factor.add_rows(A.middleRows(begin, end - begin));
    return factor.R();
  }
  MatrixXd block;
  for (Eigen::Index row = begin; row < end; row += kMaxRowsPerBlock) {
    const Eigen::Index rows = std::min(kMaxRowsPerBlock, end - row);
    block.resize(rows, n);
    block << A.middleRows(row, rows), B.middleRows(row, rows);
    factor.add_rows(block);
  }
  return factor.R();
}

}  // namespace

MatrixXd triangular_factor(const Eigen::Ref<const MatrixXd>& A,
                           const Eigen::Ref<const MatrixXd>& B) {
  if (B.cols() > 0 && B.rows() != A.rows())
    throw std::invalid_argument("triangular_factor: the two matrices have " +
                                std::to_string(A.rows()) + " and " + std::to_string(B.rows()) +
                                " rows");
  const Eigen::Index n = A.cols() + B.cols();
  if (A.rows() <= n) {
    // No factoring to do: [A B] itself (a comma initializer refuses an empty B's block).
    if (B.cols() == 0) return A;
    MatrixXd both(A.rows(), n);
    both << A, B;
    return both;
  }
  const auto rows = static_cast<int>(std::min<Eigen::Index>(A.rows(), INT_MAX));
  if (rows == A.rows() && rows >= 2 * kRowsPerChunk) {
    // Each chunk's factor on its own core, then the factors stacked in chunk order: the
    // chunks are fixed, so the result is the same on any number of threads (a serial pass
    // over 10^6 x 24 took about half a second, and a calibration report needs several).
    std::vector<MatrixXd> parts(static_cast<std::size_t>(chunk_count(rows, kRowsPerChunk)));
    parallel_chunks(rows, kRowsPerChunk, [&](int chunk, int begin, int end) {
      parts[static_cast<std::size_t>(chunk)] = factor_of_rows(A, B, begin, end);
    });
    TriangularFactor factor(n, n);
    for (const MatrixXd& part : parts) factor.add_rows(part);
    return factor.R();
  }
  return factor_of_rows(A, B, 0, A.rows());
}

MatrixXd triangular_factor(const Eigen::Ref<const MatrixXd>& A) {
  return triangular_factor(A, MatrixXd(A.rows(), 0));
}

}  // namespace kincal
