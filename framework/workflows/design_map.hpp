#pragma once
// Where a design's configurations lie among the candidates, for the design page's plot: the
// candidates' actuator values, each scaled to its range over the candidates, projected on
// their two principal directions (the plane that shows most of their spread), a sample of
// the candidates and every chosen configuration.

#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "kincal/framework/design/experiment_design.hpp"

namespace kincal {

/// The chosen configurations and a sample of the candidates on the candidates' principal
/// plane. Not computed (empty) when there are no candidates.
struct DesignMap {
  bool computed = false;
  std::vector<std::string> axes;  ///< the two directions, in words
  double explained[2] = {0, 0};   ///< share of the spread along each
  long long candidates_total = 0;
  /// (x, y) of at most `max_candidates` candidates, evenly taken, and of every chosen one, in
  /// the design's order.
  std::vector<std::array<double, 2>> candidates, chosen;
};

DesignMap design_configuration_map(const DesignCandidates& candidates,
                                   const std::vector<int>& chosen, int max_candidates = 800);

/// {"axes": [two descriptions], "explained": [share of the spread along each],
///  "candidates_total", "candidates": [[x, y], ...], "chosen": [[x, y], ...]}; null when not
/// computed.
nlohmann::ordered_json to_json(const DesignMap& map);

}  // namespace kincal
