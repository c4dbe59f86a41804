// MGH problems 20-31 and 35: defined for any number of parameters n.

#include <cmath>
#include <stdexcept>

#include "kincal/problems/mgh_definitions.hpp"

namespace kincal::problems::mgh {
namespace {

std::string sized(const char* name, int n) { return std::string(name) + "_n" + std::to_string(n); }

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

}  // namespace

Problem watson(int n) {
  double f = 0;
  if (n == 6)
    f = 2.28767e-3;
  else if (n == 9)
    f = 1.39976e-6;
  else if (n == 12)
    f = 4.72238e-10;
  else
    throw std::invalid_argument("Watson: MGH publish the minimum for n = 6, 9, 12 only");
  ProblemSpec p;
  p.name = sized("mgh20_watson", n);
  p.title = "Watson function";
  p.number = 20;
  p.n = n;
  p.m = 31;
  p.start = VectorXd::Zero(n);
  p.residuals = [n](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                    std::string*) {
    for (int k = 0; k < 29; ++k) {
      const double t = (k + 1) / 29.0;
      // sum1 = sum_{j>=1} j x_j t^(j-1), sum2 = sum_j x_j t^j (0-based j)
      double sum1 = 0, sum2 = 0, power = 1;  // power = t^j
      for (int j = 0; j < n; ++j) {
        if (j > 0) sum1 += j * x[j] * power / t;
        sum2 += x[j] * power;
        power *= t;
      }
      r[k] = sum1 - sum2 * sum2 - 1;
      if (J) {
        power = 1;
        for (int j = 0; j < n; ++j) {
          (*J)(k, j) = (j > 0 ? j * power / t : 0.0) - 2 * sum2 * power;
          power *= t;
        }
      }
    }
    r[29] = x[0];
    r[30] = x[1] - x[0] * x[0] - 1;
    if (J) {
      (*J)(29, 0) = 1;
      (*J)(30, 0) = -2 * x[0];
      (*J)(30, 1) = 1;
    }
    return true;
  };
  p.minima = {{0.5 * f, {}, false, true, "(n = " + std::to_string(n) + ")"}};
  p.note = "its start is the origin, so 10 x0 and 100 x0 are x0 again";
  return make_problem(std::move(p));
}

Problem extended_rosenbrock(int n) {
  require(n >= 2 && n % 2 == 0, "extended Rosenbrock: n must be even");
  ProblemSpec p;
  p.name = sized("mgh21_extended_rosenbrock", n);
  p.title = "Extended Rosenbrock function";
  p.number = 21;
  p.n = n;
  p.m = n;
  p.start.resize(n);
  for (int i = 0; i < n; i += 2) p.start.segment(i, 2) << -1.2, 1;
  p.residuals = [n](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                    std::string*) {
    for (int i = 0; i < n; i += 2) {
      r[i] = 10 * (x[i + 1] - x[i] * x[i]);
      r[i + 1] = 1 - x[i];
      if (J) {
        (*J)(i, i) = -20 * x[i];
        (*J)(i, i + 1) = 10;
        (*J)(i + 1, i) = -1;
      }
    }
    return true;
  };
  p.minima = {{0, std::vector<double>(n, 1.0), true, true, "at (1, ..., 1)"}};
  return make_problem(std::move(p));
}

Problem extended_powell_singular(int n) {
  require(n >= 4 && n % 4 == 0, "extended Powell singular: n must be a multiple of 4");
  ProblemSpec p;
  p.name = sized("mgh22_extended_powell_singular", n);
  p.title = "Extended Powell singular function";
  p.number = 22;
  p.n = n;
  p.m = n;
  p.start.resize(n);
  for (int i = 0; i < n; i += 4) p.start.segment(i, 4) << 3, -1, 0, 1;
  p.residuals = [n](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                    std::string*) {
    const double s5 = std::sqrt(5.0), s10 = std::sqrt(10.0);
    for (int i = 0; i < n; i += 4) {
      const double a = x[i + 1] - 2 * x[i + 2], b = x[i] - x[i + 3];
      r[i] = x[i] + 10 * x[i + 1];
      r[i + 1] = s5 * (x[i + 2] - x[i + 3]);
      r[i + 2] = a * a;
      r[i + 3] = s10 * b * b;
      if (J) {
        (*J)(i, i) = 1;
        (*J)(i, i + 1) = 10;
        (*J)(i + 1, i + 2) = s5;
        (*J)(i + 1, i + 3) = -s5;
        (*J)(i + 2, i + 1) = 2 * a;
        (*J)(i + 2, i + 2) = -4 * a;
        (*J)(i + 3, i) = 2 * s10 * b;
        (*J)(i + 3, i + 3) = -2 * s10 * b;
      }
    }
    return true;
  };
  p.minima = {{0, std::vector<double>(n, 0.0), true, true, "at the origin"}};
  return make_problem(std::move(p));
}

Problem penalty_1(int n) {
  double f = 0;
  if (n == 4)
    f = 2.24997e-5;
  else if (n == 10)
    f = 7.08765e-5;
  else
    throw std::invalid_argument("penalty function I: MGH publish the minimum for n = 4, 10 only");
  ProblemSpec p;
  p.name = sized("mgh23_penalty_1", n);
  p.title = "Penalty function I";
  p.number = 23;
  p.n = n;
  p.m = n + 1;
  p.start.resize(n);
  for (int j = 0; j < n; ++j) p.start[j] = j + 1;
  p.residuals = [n](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                    std::string*) {
    const double root_a = std::sqrt(1e-5);
    for (int j = 0; j < n; ++j) {
      r[j] = root_a * (x[j] - 1);
      if (J) (*J)(j, j) = root_a;
    }
    r[n] = x.squaredNorm() - 0.25;
    if (J) (*J).row(n) = 2 * x.transpose();
    return true;
  };
  p.minima = {{0.5 * f, {}, false, true, "(n = " + std::to_string(n) + ")"}};
  return make_problem(std::move(p));
}

Problem penalty_2(int n) {
  double f = 0;
  if (n == 4)
    f = 9.37629e-6;
  else if (n == 10)
    f = 2.93660e-4;
  else
    throw std::invalid_argument("penalty function II: MGH publish the minimum for n = 4, 10 only");
  ProblemSpec p;
  p.name = sized("mgh24_penalty_2", n);
  p.title = "Penalty function II";
  p.number = 24;
  p.n = n;
  p.m = 2 * n;
  p.start = VectorXd::Constant(n, 0.5);
  p.residuals = [n](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                    std::string*) {
    const double root_a = std::sqrt(1e-5), e_tenth = std::exp(-0.1);
    r[0] = x[0] - 0.2;
    if (J) (*J)(0, 0) = 1;
    for (int k = 1; k < n; ++k) {
      // The paper's i = k + 1: y_i = exp(i/10) + exp((i-1)/10).
      const double y = std::exp((k + 1) / 10.0) + std::exp(k / 10.0);
      const double ek = std::exp(x[k] / 10), ek1 = std::exp(x[k - 1] / 10);
      r[k] = root_a * (ek + ek1 - y);
      r[n - 1 + k] = root_a * (ek - e_tenth);
      if (J) {
        (*J)(k, k) = root_a * ek / 10;
        (*J)(k, k - 1) = root_a * ek1 / 10;
        (*J)(n - 1 + k, k) = root_a * ek / 10;
      }
    }
    double weighted = 0;
    for (int j = 0; j < n; ++j) weighted += (n - j) * x[j] * x[j];
    r[2 * n - 1] = weighted - 1;
    if (J)
      for (int j = 0; j < n; ++j) (*J)(2 * n - 1, j) = 2.0 * (n - j) * x[j];
    return true;
  };
  p.minima = {{0.5 * f, {}, false, true, "(n = " + std::to_string(n) + ")"}};
  return make_problem(std::move(p));
}

Problem variably_dimensioned(int n) {
  require(n >= 1, "variably dimensioned: n >= 1");
  ProblemSpec p;
  p.name = sized("mgh25_variably_dimensioned", n);
  p.title = "Variably dimensioned function";
  p.number = 25;
  p.n = n;
  p.m = n + 2;
  p.start.resize(n);
  for (int j = 0; j < n; ++j) p.start[j] = 1 - (j + 1.0) / n;
  p.residuals = [n](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                    std::string*) {
    double s = 0;  // sum j (x_j - 1), 1-based j
    for (int j = 0; j < n; ++j) {
      r[j] = x[j] - 1;
      s += (j + 1) * (x[j] - 1);
      if (J) (*J)(j, j) = 1;
    }
    r[n] = s;
    r[n + 1] = s * s;
    if (J)
      for (int j = 0; j < n; ++j) {
        (*J)(n, j) = j + 1;
        (*J)(n + 1, j) = 2 * s * (j + 1);
      }
    return true;
  };
  p.minima = {{0, std::vector<double>(n, 1.0), true, true, "at (1, ..., 1)"}};
  return make_problem(std::move(p));
}

Problem trigonometric(int n) {
  require(n >= 1, "trigonometric: n >= 1");
  ProblemSpec p;
  p.name = sized("mgh26_trigonometric", n);
  p.title = "Trigonometric function";
  p.number = 26;
  p.n = n;
  p.m = n;
  p.start = VectorXd::Constant(n, 1.0 / n);
  p.residuals = [n](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                    std::string*) {
    const double cos_sum = x.array().cos().sum();
    for (int i = 0; i < n; ++i) {
      const double c = std::cos(x[i]), s = std::sin(x[i]);
      r[i] = n - cos_sum + (i + 1) * (1 - c) - s;
      if (J) {
        (*J).row(i) = x.array().sin().transpose();
        (*J)(i, i) += (i + 1) * s - c;
      }
    }
    return true;
  };
  // The paper gives f = 0 only; the origin is such a point (every residual vanishes there).
  p.minima = {{0, std::vector<double>(n, 0.0), true, true, "f = 0 (at the origin, for one)"}};
  return make_problem(std::move(p));
}

Problem brown_almost_linear(int n) {
  require(n >= 2, "Brown almost-linear: n >= 2");
  ProblemSpec p;
  p.name = sized("mgh27_brown_almost_linear", n);
  p.title = "Brown almost-linear function";
  p.number = 27;
  p.n = n;
  p.m = n;
  p.start = VectorXd::Constant(n, 0.5);
  p.residuals = [n](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                    std::string*) {
    const double sum = x.sum();
    for (int i = 0; i + 1 < n; ++i) {
      r[i] = x[i] + sum - (n + 1);
      if (J) {
        (*J).row(i).setOnes();
        (*J)(i, i) = 2;
      }
    }
    r[n - 1] = x.prod() - 1;
    if (J)
      for (int j = 0; j < n; ++j) {
        double others = 1;  // product of every x_k but x_j, without dividing by x_j
        for (int k = 0; k < n; ++k)
          if (k != j) others *= x[k];
        (*J)(n - 1, j) = others;
      }
    return true;
  };
  std::vector<double> local(n, 0.0);
  local.back() = n + 1;
  p.minima = {{0, std::vector<double>(n, 1.0), true, true,
               "at (a, ..., a, a^(1-n)) with n a^n - (n+1) a^(n-1) + 1 = 0, e.g. a = 1"},
              {0.5, local, true, false, "at (0, ..., 0, n+1)"}};
  return make_problem(std::move(p));
}

Problem discrete_boundary_value(int n) {
  require(n >= 1, "discrete boundary value: n >= 1");
  ProblemSpec p;
  p.name = sized("mgh28_discrete_boundary_value", n);
  p.title = "Discrete boundary value function";
  p.number = 28;
  p.n = n;
  p.m = n;
  const double h = 1.0 / (n + 1);
  p.start.resize(n);
  for (int i = 0; i < n; ++i) p.start[i] = (i + 1) * h * ((i + 1) * h - 1);
  p.residuals = [n, h](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                       std::string*) {
    for (int i = 0; i < n; ++i) {
      const double t = (i + 1) * h, u = x[i] + t + 1;
      const double left = i > 0 ? x[i - 1] : 0.0, right = i + 1 < n ? x[i + 1] : 0.0;
      r[i] = 2 * x[i] - left - right + 0.5 * h * h * u * u * u;
      if (J) {
        (*J)(i, i) = 2 + 1.5 * h * h * u * u;
        if (i > 0) (*J)(i, i - 1) = -1;
        if (i + 1 < n) (*J)(i, i + 1) = -1;
      }
    }
    return true;
  };
  p.minima = {{0, {}, false, true, ""}};
  return make_problem(std::move(p));
}

Problem discrete_integral_equation(int n) {
  require(n >= 1, "discrete integral equation: n >= 1");
  ProblemSpec p;
  p.name = sized("mgh29_discrete_integral_equation", n);
  p.title = "Discrete integral equation function";
  p.number = 29;
  p.n = n;
  p.m = n;
  const double h = 1.0 / (n + 1);
  p.start.resize(n);
  for (int i = 0; i < n; ++i) p.start[i] = (i + 1) * h * ((i + 1) * h - 1);
  p.residuals = [n, h](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                       std::string*) {
    for (int i = 0; i < n; ++i) {
      const double ti = (i + 1) * h;
      double below = 0, above = 0;
      for (int j = 0; j < n; ++j) {
        const double tj = (j + 1) * h, u = x[j] + tj + 1, cube = u * u * u;
        // Quadrature weight of x_j in equation i, and the derivative of its term.
        const double weight = j <= i ? (1 - ti) * tj : ti * (1 - tj);
        (j <= i ? below : above) += (j <= i ? tj : (1 - tj)) * cube;
        if (J) (*J)(i, j) = 0.5 * h * weight * 3 * u * u;
      }
      r[i] = x[i] + 0.5 * h * ((1 - ti) * below + ti * above);
      if (J) (*J)(i, i) += 1;
    }
    return true;
  };
  p.minima = {{0, {}, false, true, ""}};
  return make_problem(std::move(p));
}

Problem broyden_tridiagonal(int n) {
  require(n >= 1, "Broyden tridiagonal: n >= 1");
  ProblemSpec p;
  p.name = sized("mgh30_broyden_tridiagonal", n);
  p.title = "Broyden tridiagonal function";
  p.number = 30;
  p.n = n;
  p.m = n;
  p.start = VectorXd::Constant(n, -1.0);
  p.residuals = [n](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                    std::string*) {
    for (int i = 0; i < n; ++i) {
      const double left = i > 0 ? x[i - 1] : 0.0, right = i + 1 < n ? x[i + 1] : 0.0;
      r[i] = (3 - 2 * x[i]) * x[i] - left - 2 * right + 1;
      if (J) {
        (*J)(i, i) = 3 - 4 * x[i];
        if (i > 0) (*J)(i, i - 1) = -1;
        if (i + 1 < n) (*J)(i, i + 1) = -2;
      }
    }
    return true;
  };
  p.minima = {{0, {}, false, true, ""}};
  return make_problem(std::move(p));
}

Problem broyden_banded(int n) {
  require(n >= 1, "Broyden banded: n >= 1");
  ProblemSpec p;
  p.name = sized("mgh31_broyden_banded", n);
  p.title = "Broyden banded function";
  p.number = 31;
  p.n = n;
  p.m = n;
  p.start = VectorXd::Constant(n, -1.0);
  p.residuals = [n](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                    std::string*) {
    // Band: j in [i - 5, i + 1], j != i (the paper's ml = 5, mu = 1).
    for (int i = 0; i < n; ++i) {
      r[i] = x[i] * (2 + 5 * x[i] * x[i]) + 1;
      if (J) (*J)(i, i) = 2 + 15 * x[i] * x[i];
      for (int j = std::max(0, i - 5); j <= std::min(n - 1, i + 1); ++j) {
        if (j == i) continue;
        r[i] -= x[j] * (1 + x[j]);
        if (J) (*J)(i, j) = -(1 + 2 * x[j]);
      }
    }
    return true;
  };
  p.minima = {{0, {}, false, true, ""}};
  return make_problem(std::move(p));
}

Problem chebyquad(int n) {
  double f = 0;
  if (n == 8)
    f = 3.51687e-3;
  else if (n == 10)
    f = 6.50395e-3;
  else if (n < 1 || n > 10)
    throw std::invalid_argument("Chebyquad: MGH publish the minimum for n = m = 1..10 only");
  ProblemSpec p;
  p.name = sized("mgh35_chebyquad", n);
  p.title = "Chebyquad function";
  p.number = 35;
  p.n = n;
  p.m = n;
  p.start.resize(n);
  for (int j = 0; j < n; ++j) p.start[j] = (j + 1.0) / (n + 1);
  p.residuals = [n](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                    std::string*) {
    // r_i = (1/n) sum_j T_i(2 x_j - 1) - integral_0^1 T_i(2u - 1) du, i = 1..m, with the
    // shifted Chebyshev polynomials by their recurrence (values and derivatives in y).
    r.setZero();
    for (int j = 0; j < n; ++j) {
      const double y = 2 * x[j] - 1;
      double t_prev = 1, t = y, d_prev = 0, d = 1;  // T_0, T_1 and their derivatives
      for (int i = 0; i < n; ++i) {
        r[i] += t / n;
        if (J) (*J)(i, j) = 2 * d / n;  // dT/dx = 2 dT/dy
        const double t_next = 2 * y * t - t_prev, d_next = 2 * t + 2 * y * d - d_prev;
        t_prev = t;
        t = t_next;
        d_prev = d;
        d = d_next;
      }
    }
    for (int i = 0; i < n; ++i) {
      const int degree = i + 1;
      if (degree % 2 == 0) r[i] += 1.0 / (degree * degree - 1.0);
    }
    return true;
  };
  p.minima = {{0.5 * f, {}, false, true, "(m = n = " + std::to_string(n) + ")"}};
  return make_problem(std::move(p));
}

}  // namespace kincal::problems::mgh
