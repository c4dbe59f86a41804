// MGH problems 1-5, 7, 13 and 14: fixed sizes, two to four parameters.

#include <cmath>

#include "kincal/problems/mgh_definitions.hpp"

namespace kincal::problems::mgh {

Problem rosenbrock() {
  ProblemSpec p;
  p.name = "mgh01_rosenbrock";
  p.title = "Rosenbrock function";
  p.number = 1;
  p.n = 2;
  p.m = 2;
  p.start = vec({-1.2, 1});
  p.residuals = [](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                   std::string*) {
    r[0] = 10 * (x[1] - x[0] * x[0]);
    r[1] = 1 - x[0];
    if (J) *J << -20 * x[0], 10, -1, 0;
    return true;
  };
  p.minima = {{0, {1, 1}, true, true, "at (1, 1)"}};
  return make_problem(std::move(p));
}

Problem freudenstein_roth() {
  ProblemSpec p;
  p.name = "mgh02_freudenstein_roth";
  p.title = "Freudenstein and Roth function";
  p.number = 2;
  p.n = 2;
  p.m = 2;
  p.start = vec({0.5, -2});
  p.residuals = [](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                   std::string*) {
    const double y = x[1];
    r[0] = -13 + x[0] + ((5 - y) * y - 2) * y;
    r[1] = -29 + x[0] + ((y + 1) * y - 14) * y;
    if (J) *J << 1, (10 - 3 * y) * y - 2, 1, (3 * y + 2) * y - 14;
    return true;
  };
  p.minima = {{0, {5, 4}, true, true, "at (5, 4)"},
              {0.5 * 48.9842, {11.41, -0.8968}, false, false, "at (11.41..., -0.8968...)"}};
  return make_problem(std::move(p));
}

Problem powell_badly_scaled() {
  ProblemSpec p;
  p.name = "mgh03_powell_badly_scaled";
  p.title = "Powell badly scaled function";
  p.number = 3;
  p.n = 2;
  p.m = 2;
  p.start = vec({0, 1});
  p.residuals = [](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                   std::string*) {
    const double e0 = std::exp(-x[0]), e1 = std::exp(-x[1]);
    r[0] = 1e4 * x[0] * x[1] - 1;
    r[1] = e0 + e1 - 1.0001;
    if (J) *J << 1e4 * x[1], 1e4 * x[0], -e0, -e1;
    return true;
  };
  p.minima = {{0, {1.098e-5, 9.106}, false, true, "at (1.098...e-5, 9.106...)"}};
  return make_problem(std::move(p));
}

Problem brown_badly_scaled() {
  ProblemSpec p;
  p.name = "mgh04_brown_badly_scaled";
  p.title = "Brown badly scaled function";
  p.number = 4;
  p.n = 2;
  p.m = 3;
  p.start = vec({1, 1});
  p.residuals = [](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                   std::string*) {
    r[0] = x[0] - 1e6;
    r[1] = x[1] - 2e-6;
    r[2] = x[0] * x[1] - 2;
    if (J) *J << 1, 0, 0, 1, x[1], x[0];
    return true;
  };
  p.minima = {{0, {1e6, 2e-6}, true, true, "at (1e6, 2e-6)"}};
  return make_problem(std::move(p));
}

Problem beale() {
  ProblemSpec p;
  p.name = "mgh05_beale";
  p.title = "Beale function";
  p.number = 5;
  p.n = 2;
  p.m = 3;
  p.start = vec({1, 1});
  p.residuals = [](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                   std::string*) {
    static const double y[3] = {1.5, 2.25, 2.625};
    double power = 1;  // x2^(i-1)
    for (int i = 0; i < 3; ++i) {
      const double next = power * x[1];  // x2^i
      r[i] = y[i] - x[0] * (1 - next);
      if (J) {
        (*J)(i, 0) = -(1 - next);
        (*J)(i, 1) = x[0] * (i + 1) * power;
      }
      power = next;
    }
    return true;
  };
  p.minima = {{0, {3, 0.5}, true, true, "at (3, 0.5)"}};
  return make_problem(std::move(p));
}

Problem helical_valley() {
  ProblemSpec p;
  p.name = "mgh07_helical_valley";
  p.title = "Helical valley function";
  p.number = 7;
  p.n = 3;
  p.m = 3;
  p.start = vec({-1, 0, 0});
  p.residuals = [](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                   std::string* why) {
    const double rho2 = x[0] * x[0] + x[1] * x[1];
    if (rho2 == 0) {
      if (why) *why = "mgh07_helical_valley: theta is undefined at x1 = x2 = 0";
      return false;
    }
    // The paper's theta: a branch of atan(x2/x1)/(2 pi) in (-1/4, 3/4), not atan2.
    constexpr double kTwoPi = 6.283185307179586476925;
    double theta;
    if (x[0] > 0)
      theta = std::atan(x[1] / x[0]) / kTwoPi;
    else if (x[0] < 0)
      theta = std::atan(x[1] / x[0]) / kTwoPi + 0.5;
    else
      theta = x[1] > 0 ? 0.25 : -0.25;
    const double rho = std::sqrt(rho2);
    r[0] = 10 * (x[2] - 10 * theta);
    r[1] = 10 * (rho - 1);
    r[2] = x[2];
    if (J) {
      // d theta / dx1 = -x2 / (2 pi rho^2), d theta / dx2 = x1 / (2 pi rho^2)
      *J << 100 * x[1] / (kTwoPi * rho2), -100 * x[0] / (kTwoPi * rho2), 10, 10 * x[0] / rho,
          10 * x[1] / rho, 0, 0, 0, 1;
    }
    return true;
  };
  p.minima = {{0, {1, 0, 0}, true, true, "at (1, 0, 0)"}};
  return make_problem(std::move(p));
}

Problem powell_singular() {
  ProblemSpec p;
  p.name = "mgh13_powell_singular";
  p.title = "Powell singular function";
  p.number = 13;
  p.n = 4;
  p.m = 4;
  p.start = vec({3, -1, 0, 1});
  p.residuals = [](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                   std::string*) {
    const double s5 = std::sqrt(5.0), s10 = std::sqrt(10.0);
    const double a = x[1] - 2 * x[2], b = x[0] - x[3];
    r[0] = x[0] + 10 * x[1];
    r[1] = s5 * (x[2] - x[3]);
    r[2] = a * a;
    r[3] = s10 * b * b;
    if (J) *J << 1, 10, 0, 0, 0, 0, s5, -s5, 0, 2 * a, -4 * a, 0, 2 * s10 * b, 0, 0, -2 * s10 * b;
    return true;
  };
  p.minima = {{0, {0, 0, 0, 0}, true, true, "at the origin"}};
  return make_problem(std::move(p));
}

Problem wood() {
  ProblemSpec p;
  p.name = "mgh14_wood";
  p.title = "Wood function";
  p.number = 14;
  p.n = 4;
  p.m = 6;
  p.start = vec({-3, -1, -3, -1});
  p.residuals = [](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                   std::string*) {
    const double s90 = std::sqrt(90.0), s10 = std::sqrt(10.0);
    r[0] = 10 * (x[1] - x[0] * x[0]);
    r[1] = 1 - x[0];
    r[2] = s90 * (x[3] - x[2] * x[2]);
    r[3] = 1 - x[2];
    r[4] = s10 * (x[1] + x[3] - 2);
    r[5] = (x[1] - x[3]) / s10;
    if (J) {
      *J << -20 * x[0], 10, 0, 0,      //
          -1, 0, 0, 0,                 //
          0, 0, -2 * s90 * x[2], s90,  //
          0, 0, -1, 0,                 //
          0, s10, 0, s10,              //
          0, 1 / s10, 0, -1 / s10;
    }
    return true;
  };
  p.minima = {{0, {1, 1, 1, 1}, true, true, "at (1, 1, 1, 1)"}};
  return make_problem(std::move(p));
}

}  // namespace kincal::problems::mgh
