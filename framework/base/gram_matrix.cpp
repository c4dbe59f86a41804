#include "kincal/framework/base/gram_matrix.hpp"

#include <climits>
#include <vector>

#include "kincal/framework/base/parallel.hpp"

namespace kincal {

namespace {

constexpr int kRowsPerChunk = 65536;

}  // namespace

void gram_lower(const MatrixXd& B, MatrixXd& H) {
  H.setZero();
  const Eigen::Index m = B.rows();
  if (m < 2 * kRowsPerChunk || m > INT_MAX) {
    H.selfadjointView<Eigen::Lower>().rankUpdate(B.transpose());
    return;
  }
  const int rows = static_cast<int>(m);
  std::vector<MatrixXd> parts(static_cast<std::size_t>(chunk_count(rows, kRowsPerChunk)));
  parallel_chunks(rows, kRowsPerChunk, [&](int chunk, int begin, int end) {
    MatrixXd& part = parts[static_cast<std::size_t>(chunk)];
    part.setZero(B.cols(), B.cols());
    part.selfadjointView<Eigen::Lower>().rankUpdate(B.middleRows(begin, end - begin).transpose());
  });
  for (const MatrixXd& part : parts) H.triangularView<Eigen::Lower>() += part;
}

}  // namespace kincal
