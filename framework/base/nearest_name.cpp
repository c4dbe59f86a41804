#include "kincal/framework/base/nearest_name.hpp"

#include <algorithm>

namespace kincal {

int edit_distance(const std::string& a, const std::string& b) {
  const std::size_t n = a.size(), m = b.size();
  // Three rows of the dynamic programme: the swap looks two rows back.
  std::vector<int> two_back(m + 1), previous(m + 1), current(m + 1);
  for (std::size_t j = 0; j <= m; ++j) previous[j] = static_cast<int>(j);
  for (std::size_t i = 1; i <= n; ++i) {
    current[0] = static_cast<int>(i);
    for (std::size_t j = 1; j <= m; ++j) {
      const int cost = a[i - 1] == b[j - 1] ? 0 : 1;
      current[j] = std::min({previous[j] + 1, current[j - 1] + 1, previous[j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        current[j] = std::min(current[j], two_back[j - 2] + 1);
    }
    two_back.swap(previous);
    previous.swap(current);
  }
  return previous[m];
}

std::string nearest_name(const std::string& given, const std::vector<std::string>& known) {
  if (given.empty()) return "";
  const int allowed = given.size() <= 4 ? 1 : given.size() <= 8 ? 2 : 3;
  std::string best;
  int best_distance = allowed + 1;
  for (const std::string& name : known) {
    const int d = edit_distance(given, name);
    if (d < best_distance) {
      best_distance = d;
      best = name;
    }
  }
  if (!best.empty()) return best;
  if (given.size() < 3) return "";
  std::string prefixed;
  for (const std::string& name : known)
    if (name.compare(0, given.size(), given) == 0) {
      if (!prefixed.empty()) return "";  // ambiguous
      prefixed = name;
    }
  return prefixed;
}

}  // namespace kincal
