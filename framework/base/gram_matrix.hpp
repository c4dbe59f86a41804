#pragma once
// B^T B of a tall matrix on all cores: lm forms it at every iteration, and at 10^6 readings and
// 24 parameters Eigen's one-threaded rank update took about 0.3 s of each.

#include "kincal/framework/base/types.hpp"

namespace kincal {

/// The lower triangle of B^T B into `H` (n x n, presized; the strict upper triangle zero). From 2 *
/// 65536 rows on, partial products over fixed chunks of 65536 rows run on all cores and are added
/// in chunk order, so the result is the same on any number of threads; below, one rank update in
/// this thread, which allocates nothing.
void gram_lower(const MatrixXd& B, MatrixXd& H);

}  // namespace kincal
