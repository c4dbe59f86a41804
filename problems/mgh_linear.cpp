// MGH problems 32-34: linear residuals, so their minima are known in closed form for any
// n <= m.

#include <stdexcept>

#include "kincal/problems/mgh_definitions.hpp"

namespace kincal::problems::mgh {
namespace {

std::string sized(const char* name, int n, int m) {
  return std::string(name) + "_n" + std::to_string(n) + "_m" + std::to_string(m);
}

void require_sizes(int n, int m, const char* what) {
  if (n < 1 || m < n) throw std::invalid_argument(std::string(what) + ": 1 <= n <= m");
}

}  // namespace

Problem linear_full_rank(int n, int m) {
  require_sizes(n, m, "linear function - full rank");
  ProblemSpec p;
  p.name = sized("mgh32_linear_full_rank", n, m);
  p.title = "Linear function - full rank";
  p.number = 32;
  p.n = n;
  p.m = m;
  p.start = VectorXd::Ones(n);
  p.residuals = [n, m](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                       std::string*) {
    const double common = 2.0 / m * x.sum() + 1;
    for (int i = 0; i < m; ++i) {
      r[i] = (i < n ? x[i] : 0.0) - common;
      if (J) {
        (*J).row(i).setConstant(-2.0 / m);
        if (i < n) (*J)(i, i) += 1;
      }
    }
    return true;
  };
  p.minima = {
      {0.5 * (m - n), std::vector<double>(n, -1.0), true, true, "f = m - n at (-1, ..., -1)"}};
  return make_problem(std::move(p));
}

Problem linear_rank_1(int n, int m) {
  require_sizes(n, m, "linear function - rank 1");
  ProblemSpec p;
  p.name = sized("mgh33_linear_rank_1", n, m);
  p.title = "Linear function - rank 1";
  p.number = 33;
  p.n = n;
  p.m = m;
  p.start = VectorXd::Ones(n);
  p.residuals = [n, m](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                       std::string*) {
    double weighted = 0;  // sum j x_j, 1-based j
    for (int j = 0; j < n; ++j) weighted += (j + 1) * x[j];
    for (int i = 0; i < m; ++i) {
      r[i] = (i + 1) * weighted - 1;
      if (J)
        for (int j = 0; j < n; ++j) (*J)(i, j) = (i + 1.0) * (j + 1);
    }
    return true;
  };
  // Any point with sum j x_j = 3 / (2m + 1) is a minimiser; the first coordinate alone is one.
  std::vector<double> minimiser(n, 0.0);
  minimiser[0] = 3.0 / (2 * m + 1);
  p.minima = {{0.5 * m * (m - 1) / (2.0 * (2 * m + 1)), minimiser, true, true,
               "f = m(m-1) / (2(2m+1)) wherever sum j x_j = 3 / (2m+1)"}};
  return make_problem(std::move(p));
}

Problem linear_rank_1_zero_columns(int n, int m) {
  require_sizes(n, m, "linear function - rank 1 with zero columns and rows");
  if (n < 3 || m < 3)
    throw std::invalid_argument("linear function - rank 1 with zero columns: n, m >= 3");
  ProblemSpec p;
  p.name = sized("mgh34_linear_rank_1_zero", n, m);
  p.title = "Linear function - rank 1 with zero columns and rows";
  p.number = 34;
  p.n = n;
  p.m = m;
  p.start = VectorXd::Ones(n);
  p.residuals = [n, m](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                       std::string*) {
    double weighted = 0;  // sum_{j=2}^{n-1} j x_j, 1-based j: the first and last x do not enter
    for (int j = 1; j + 1 < n; ++j) weighted += (j + 1) * x[j];
    r[0] = -1;
    r[m - 1] = -1;
    for (int i = 1; i + 1 < m; ++i) {
      r[i] = i * weighted - 1;
      if (J)
        for (int j = 1; j + 1 < n; ++j) (*J)(i, j) = i * (j + 1.0);
    }
    return true;
  };
  std::vector<double> minimiser(n, 0.0);
  minimiser[1] = 3.0 / (2.0 * (2 * m - 3));
  p.minima = {{0.5 * (m * m + 3.0 * m - 6) / (2.0 * (2 * m - 3)), minimiser, true, true,
               "f = (m^2 + 3m - 6) / (2(2m-3)) wherever sum_{j=2}^{n-1} j x_j = 3 / (2m-3)"}};
  p.note = "x1 and xn never enter the residuals: their Jacobian columns are zero everywhere";
  return make_problem(std::move(p));
}

}  // namespace kincal::problems::mgh
