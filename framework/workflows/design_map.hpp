#pragma once
// Where a design's configurations lie among the candidates, for the design page's plot: the
// candidates' actuator values, each scaled to its range over the candidates, projected on
// their two principal directions (the plane that shows most of their spread), a sample of
// the candidates and every chosen configuration.

#include <nlohmann/json.hpp>
#include <vector>

#include "kincal/framework/design/experiment_design.hpp"

namespace kincal {

/// {"axes": [two descriptions], "explained": [share of the spread along each],
///  "candidates_total", "candidates": [[x, y], ...] (at most `max_candidates`, evenly taken),
///  "chosen": [[x, y], ...] (one per chosen candidate, in the design's order)}.
nlohmann::ordered_json design_configuration_map(const DesignCandidates& candidates,
                                                const std::vector<int>& chosen,
                                                int max_candidates = 800);

}  // namespace kincal
