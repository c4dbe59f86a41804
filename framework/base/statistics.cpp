#include "kincal/framework/base/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace kincal {

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  const double position = std::clamp(q, 0.0, 1.0) * (values.size() - 1);
  const auto lower = static_cast<std::size_t>(std::floor(position));
  const std::size_t upper = std::min(lower + 1, values.size() - 1);
  const double weight = position - lower;
  if (weight == 0.0 || values[lower] == values[upper]) return values[lower];
  return values[lower] + weight * (values[upper] - values[lower]);
}

namespace {

// Regularised upper incomplete gamma Q(a, x): the series of P below a + 1, Lentz's continued
// fraction of Q above (both converge fast there).
double gamma_q(double a, double x) {
  if (x <= 0) return 1.0;
  const double log_prefactor = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 10000 && std::abs(term) > 1e-16 * std::abs(sum); ++n) {
      term *= x / (a + n);
      sum += term;
    }
    return std::max(0.0, 1.0 - sum * std::exp(log_prefactor));
  }
  constexpr double kTiny = 1e-300;
  double b = x + 1 - a, c = 1 / kTiny, d = 1 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1) < 1e-16) break;
  }
  return std::exp(log_prefactor) * h;
}

// The continued fraction of the regularised incomplete beta I_x(a, b) (the even and odd
// steps of its standard expansion), evaluated by Lentz's method; it converges fast for
// x < (a + 1) / (a + b + 2), and incomplete_beta() uses the symmetry I_x(a, b) =
// 1 - I_{1-x}(b, a) elsewhere.
double beta_continued_fraction(double a, double b, double x) {
  constexpr double kTiny = 1e-300;
  const auto guard = [](double v) { return std::abs(v) < kTiny ? kTiny : v; };
  double c = 1, d = 1 / guard(1 - (a + b) * x / (a + 1)), h = d;
  for (int m = 1; m < 10000; ++m) {
    const double even = m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m));
    d = 1 / guard(1 + even * d);
    c = guard(1 + even / c);
    h *= d * c;
    const double odd = -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1));
    d = 1 / guard(1 + odd * d);
    c = guard(1 + odd / c);
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1) < 1e-16) break;
  }
  return h;
}

double incomplete_beta(double a, double b, double x) {
  if (x <= 0) return 0;
  if (x >= 1) return 1;
  const double log_prefactor =
      std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x);
  if (x < (a + 1) / (a + b + 2))
    return std::exp(log_prefactor) * beta_continued_fraction(a, b, x) / a;
  return 1 - std::exp(log_prefactor) * beta_continued_fraction(b, a, 1 - x) / b;
}

}  // namespace

double f_upper_tail(double f, double d1, double d2) {
  if (!(f > 0)) return 1.0;
  if (std::isinf(f)) return 0.0;
  return std::clamp(incomplete_beta(d2 / 2, d1 / 2, d2 / (d2 + d1 * f)), 0.0, 1.0);
}

double chi_square_upper_tail(double x, double k) { return gamma_q(k / 2, x / 2); }

}  // namespace kincal
