#pragma once
// Order statistics for Monte Carlo summaries, and the chi-square and F tails the fit checks
// use.

#include <vector>

namespace kincal {

/// The q-quantile (0 <= q <= 1) with linear interpolation between order statistics;
/// NaN for an empty sample. Infinite values sort last, so a few failures show in p90.
double quantile(std::vector<double> values, double q);
inline double median(std::vector<double> values) { return quantile(std::move(values), 0.5); }

/// P(X >= x) for X chi-square with k degrees of freedom (k > 0).
double chi_square_upper_tail(double x, double k);

/// P(X >= f) for X Fisher-Snedecor F with d1 and d2 degrees of freedom (d1, d2 > 0): the
/// test of whether extra regressors explain more of a residual than noise would, when the
/// noise's variance is itself estimated from d2 residual degrees of freedom.
double f_upper_tail(double f, double d1, double d2);

}  // namespace kincal
