#include "kincal/framework/statistics.hpp"

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

}  // namespace kincal
