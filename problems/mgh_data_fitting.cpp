// MGH problems 6, 8-12 and 15-19: fitting models (exponentials, rationals, Gaussians) to data.

#include <cmath>
#include <stdexcept>

#include "kincal/problems/mgh_definitions.hpp"

namespace kincal::problems::mgh {
namespace {

bool fail(std::string* why, const std::string& reason) {
  if (why) *why = reason;
  return false;
}

}  // namespace

Problem jennrich_sampson(int m) {
  if (m != 10)
    throw std::invalid_argument("Jennrich and Sampson: MGH publish the minimum for m = 10 only");
  ProblemSpec p;
  p.name = "mgh06_jennrich_sampson";
  p.title = "Jennrich and Sampson function";
  p.number = 6;
  p.n = 2;
  p.m = m;
  p.start = vec({0.3, 0.4});
  p.residuals = [m](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                    std::string*) {
    for (int k = 0; k < m; ++k) {
      const double i = k + 1, e0 = std::exp(i * x[0]), e1 = std::exp(i * x[1]);
      r[k] = 2 + 2 * i - (e0 + e1);
      if (J) (*J).row(k) << -i * e0, -i * e1;
    }
    return true;
  };
  p.minima = {{0.5 * 124.362, {0.2578, 0.2578}, false, true, "at x1 = x2 = 0.2578... (m = 10)"}};
  return make_problem(std::move(p));
}

Problem bard() {
  ProblemSpec p;
  p.name = "mgh08_bard";
  p.title = "Bard function";
  p.number = 8;
  p.n = 3;
  p.m = 15;
  p.start = vec({1, 1, 1});
  p.residuals = [](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                   std::string* why) {
    static const double y[15] = {0.14, 0.18, 0.22, 0.25, 0.29, 0.32, 0.35, 0.39,
                                 0.37, 0.58, 0.73, 0.96, 1.34, 2.10, 4.39};
    for (int k = 0; k < 15; ++k) {
      const double u = k + 1, v = 16 - u, w = std::min(u, v);
      const double d = v * x[1] + w * x[2];
      if (d == 0) return fail(why, "mgh08_bard: division by zero (v x2 + w x3 = 0)");
      r[k] = y[k] - (x[0] + u / d);
      if (J) (*J).row(k) << -1, u * v / (d * d), u * w / (d * d);
    }
    return true;
  };
  p.minima = {{0.5 * 8.21487e-3, {}, false, true, ""},
              {0.5 * 17.4286, {}, false, false, "as x2, x3 -> -inf with x1 = 0.8406..."}};
  return make_problem(std::move(p));
}

Problem gaussian() {
  ProblemSpec p;
  p.name = "mgh09_gaussian";
  p.title = "Gaussian function";
  p.number = 9;
  p.n = 3;
  p.m = 15;
  p.start = vec({0.4, 1, 0});
  p.residuals = [](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                   std::string*) {
    static const double y[15] = {0.0009, 0.0044, 0.0175, 0.0540, 0.1295, 0.2420, 0.3521, 0.3989,
                                 0.3521, 0.2420, 0.1295, 0.0540, 0.0175, 0.0044, 0.0009};
    for (int k = 0; k < 15; ++k) {
      const double t = (8.0 - (k + 1)) / 2, d = t - x[2];
      const double e = std::exp(-0.5 * x[1] * d * d);
      r[k] = x[0] * e - y[k];
      if (J) (*J).row(k) << e, -0.5 * x[0] * e * d * d, x[0] * e * x[1] * d;
    }
    return true;
  };
  p.minima = {{0.5 * 1.12793e-8, {}, false, true, ""}};
  return make_problem(std::move(p));
}

Problem meyer() {
  ProblemSpec p;
  p.name = "mgh10_meyer";
  p.title = "Meyer function";
  p.number = 10;
  p.n = 3;
  p.m = 16;
  p.start = vec({0.02, 4000, 250});
  p.residuals = [](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                   std::string* why) {
    static const double y[16] = {34780, 28610, 23650, 19630, 16370, 13720, 11540, 9744,
                                 8261,  7030,  6005,  5147,  4427,  3820,  3307,  2872};
    for (int k = 0; k < 16; ++k) {
      const double t = 45 + 5.0 * (k + 1), d = t + x[2];
      if (d == 0) return fail(why, "mgh10_meyer: division by zero (t + x3 = 0)");
      const double e = std::exp(x[1] / d);
      r[k] = x[0] * e - y[k];
      if (J) (*J).row(k) << e, x[0] * e / d, -x[0] * e * x[1] / (d * d);
    }
    return true;
  };
  p.minima = {{0.5 * 87.9458, {}, false, true, ""}};
  return make_problem(std::move(p));
}

Problem gulf(int m) {
  if (m < 3 || m > 100) throw std::invalid_argument("Gulf research and development: 3 <= m <= 100");
  ProblemSpec p;
  p.name = "mgh11_gulf";
  p.title = "Gulf research and development function";
  p.number = 11;
  p.n = 3;
  p.m = m;
  p.start = vec({5, 2.5, 0.15});
  p.residuals = [m](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                    std::string* why) {
    if (x[0] == 0) return fail(why, "mgh11_gulf: division by zero (x1 = 0)");
    for (int k = 0; k < m; ++k) {
      const double t = (k + 1) / 100.0;
      const double y = 25 + std::pow(-50 * std::log(t), 2.0 / 3.0);
      const double a = std::abs(y - x[1]);
      const double power = std::pow(a, x[2]);  // |y - x2|^x3
      const double e = std::exp(-power / x[0]);
      r[k] = e - t;
      if (J) {
        // d|y - x2|/dx2 = -sign(y - x2); at a = 0 the power term and its derivatives vanish
        // (x3 > 0 at every point the paper considers).
        const double sign = y > x[1] ? 1.0 : (y < x[1] ? -1.0 : 0.0);
        const double d_power_d_centre = a > 0 ? -sign * x[2] * power / a : 0.0;
        const double d_power_d_exponent = a > 0 ? power * std::log(a) : 0.0;
        (*J).row(k) << e * power / (x[0] * x[0]), -e * d_power_d_centre / x[0],
            -e * d_power_d_exponent / x[0];
      }
    }
    return true;
  };
  p.minima = {{0, {50, 25, 1.5}, true, true, "at (50, 25, 1.5)"}};
  p.note = "its 10 x0 start is the minimiser (50, 25, 1.5) itself";
  return make_problem(std::move(p));
}

Problem box_3d(int m) {
  if (m < 3) throw std::invalid_argument("Box three-dimensional: m >= 3");
  ProblemSpec p;
  p.name = "mgh12_box_3d";
  p.title = "Box three-dimensional function";
  p.number = 12;
  p.n = 3;
  p.m = m;
  p.start = vec({0, 10, 20});
  p.residuals = [m](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                    std::string*) {
    for (int k = 0; k < m; ++k) {
      const double t = 0.1 * (k + 1);
      const double e0 = std::exp(-t * x[0]), e1 = std::exp(-t * x[1]);
      const double c = std::exp(-t) - std::exp(-10 * t);
      r[k] = e0 - e1 - x[2] * c;
      if (J) (*J).row(k) << -t * e0, t * e1, -c;
    }
    return true;
  };
  p.minima = {
      {0, {1, 10, 1}, true, true, "at (1, 10, 1), (10, 1, -1), and wherever x1 = x2, x3 = 0"}};
  return make_problem(std::move(p));
}

Problem kowalik_osborne() {
  ProblemSpec p;
  p.name = "mgh15_kowalik_osborne";
  p.title = "Kowalik and Osborne function";
  p.number = 15;
  p.n = 4;
  p.m = 11;
  p.start = vec({0.25, 0.39, 0.415, 0.39});
  p.residuals = [](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                   std::string* why) {
    static const double y[11] = {0.1957, 0.1947, 0.1735, 0.1600, 0.0844, 0.0627,
                                 0.0456, 0.0342, 0.0323, 0.0235, 0.0246};
    static const double u[11] = {4, 2, 1, 0.5, 0.25, 0.167, 0.125, 0.100, 0.0833, 0.0714, 0.0625};
    for (int k = 0; k < 11; ++k) {
      const double num = u[k] * (u[k] + x[1]), den = u[k] * (u[k] + x[2]) + x[3];
      if (den == 0) return fail(why, "mgh15_kowalik_osborne: division by zero");
      r[k] = y[k] - x[0] * num / den;
      if (J)
        (*J).row(k) << -num / den, -x[0] * u[k] / den, x[0] * num * u[k] / (den * den),
            x[0] * num / (den * den);
    }
    return true;
  };
  p.minima = {
      {0.5 * 3.07505e-4, {}, false, true, ""},
      {0.5 * 1.02734e-3, {}, false, false, "as x1 -> +inf, x3, x4 -> -inf with x2 = -14.07..."}};
  return make_problem(std::move(p));
}

Problem brown_dennis(int m) {
  if (m != 20)
    throw std::invalid_argument("Brown and Dennis: MGH publish the minimum for m = 20 only");
  ProblemSpec p;
  p.name = "mgh16_brown_dennis";
  p.title = "Brown and Dennis function";
  p.number = 16;
  p.n = 4;
  p.m = m;
  p.start = vec({25, 5, -5, -1});
  p.residuals = [m](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                    std::string*) {
    for (int k = 0; k < m; ++k) {
      const double t = (k + 1) / 5.0, s = std::sin(t);
      const double a = x[0] + t * x[1] - std::exp(t), b = x[2] + x[3] * s - std::cos(t);
      r[k] = a * a + b * b;
      if (J) (*J).row(k) << 2 * a, 2 * a * t, 2 * b, 2 * b * s;
    }
    return true;
  };
  p.minima = {{0.5 * 85822.2, {}, false, true, "(m = 20)"}};
  return make_problem(std::move(p));
}

Problem osborne_1() {
  ProblemSpec p;
  p.name = "mgh17_osborne_1";
  p.title = "Osborne 1 function";
  p.number = 17;
  p.n = 5;
  p.m = 33;
  p.start = vec({0.5, 1.5, -1, 0.01, 0.02});
  p.residuals = [](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                   std::string*) {
    static const double y[33] = {0.844, 0.908, 0.932, 0.936, 0.925, 0.908, 0.881, 0.850, 0.818,
                                 0.784, 0.751, 0.718, 0.685, 0.658, 0.628, 0.603, 0.580, 0.558,
                                 0.538, 0.522, 0.506, 0.490, 0.478, 0.467, 0.457, 0.448, 0.438,
                                 0.431, 0.424, 0.420, 0.414, 0.411, 0.406};
    for (int k = 0; k < 33; ++k) {
      const double t = 10.0 * k, e3 = std::exp(-t * x[3]), e4 = std::exp(-t * x[4]);
      r[k] = y[k] - (x[0] + x[1] * e3 + x[2] * e4);
      if (J) (*J).row(k) << -1, -e3, -e4, t * x[1] * e3, t * x[2] * e4;
    }
    return true;
  };
  p.minima = {{0.5 * 5.46489e-5, {}, false, true, ""}};
  return make_problem(std::move(p));
}

Problem biggs_exp6(int m) {
  if (m != 13)
    throw std::invalid_argument("Biggs EXP6: MGH publish the local minimum for m = 13 only");
  ProblemSpec p;
  p.name = "mgh18_biggs_exp6";
  p.title = "Biggs EXP6 function";
  p.number = 18;
  p.n = 6;
  p.m = m;
  p.start = vec({1, 2, 1, 1, 1, 1});
  p.residuals = [m](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                    std::string*) {
    for (int k = 0; k < m; ++k) {
      const double t = 0.1 * (k + 1);
      const double y = std::exp(-t) - 5 * std::exp(-10 * t) + 3 * std::exp(-4 * t);
      const double e0 = std::exp(-t * x[0]), e1 = std::exp(-t * x[1]), e4 = std::exp(-t * x[4]);
      r[k] = x[2] * e0 - x[3] * e1 + x[5] * e4 - y;
      if (J) (*J).row(k) << -t * x[2] * e0, t * x[3] * e1, e0, -e1, -t * x[5] * e4, e4;
    }
    return true;
  };
  // The data are generated by the model at (1, 10, 1, 5, 4, 3), so its residuals vanish there
  // for any m; the paper's 5.65565e-3 (m = 13) is a local minimum.
  p.minima = {{0, {1, 10, 1, 5, 4, 3}, true, true, "at (1, 10, 1, 5, 4, 3)"},
              {0.5 * 5.65565e-3, {}, false, false, "(m = 13)"}};
  return make_problem(std::move(p));
}

Problem osborne_2() {
  ProblemSpec p;
  p.name = "mgh19_osborne_2";
  p.title = "Osborne 2 function";
  p.number = 19;
  p.n = 11;
  p.m = 65;
  p.start = vec({1.3, 0.65, 0.65, 0.7, 0.6, 3, 5, 7, 2, 4.5, 5.5});
  p.residuals = [](const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* J,
                   std::string*) {
    static const double y[65] = {
        1.366, 1.191, 1.112, 1.013, 0.991, 0.885, 0.831, 0.847, 0.786, 0.725, 0.746, 0.679, 0.608,
        0.655, 0.616, 0.606, 0.602, 0.626, 0.651, 0.724, 0.649, 0.649, 0.694, 0.644, 0.624, 0.661,
        0.612, 0.558, 0.533, 0.495, 0.500, 0.423, 0.395, 0.375, 0.372, 0.391, 0.396, 0.405, 0.428,
        0.429, 0.523, 0.562, 0.607, 0.653, 0.672, 0.708, 0.633, 0.668, 0.645, 0.632, 0.591, 0.559,
        0.597, 0.625, 0.739, 0.710, 0.729, 0.720, 0.636, 0.581, 0.428, 0.292, 0.162, 0.098, 0.054};
    for (int k = 0; k < 65; ++k) {
      const double t = k / 10.0;
      const double e0 = std::exp(-t * x[4]);
      double model = x[0] * e0;
      if (J) {
        (*J)(k, 0) = -e0;
        (*J)(k, 4) = t * x[0] * e0;
      }
      // Three Gaussian bumps: amplitude x[1 + b], width x[5 + b], centre x[8 + b].
      for (int b = 0; b < 3; ++b) {
        const double d = t - x[8 + b], e = std::exp(-d * d * x[5 + b]);
        model += x[1 + b] * e;
        if (J) {
          (*J)(k, 1 + b) = -e;
          (*J)(k, 5 + b) = x[1 + b] * d * d * e;
          (*J)(k, 8 + b) = -2 * x[1 + b] * x[5 + b] * d * e;
        }
      }
      r[k] = y[k] - model;
    }
    return true;
  };
  p.minima = {{0.5 * 4.01377e-2, {}, false, true, ""}};
  return make_problem(std::move(p));
}

}  // namespace kincal::problems::mgh
