#pragma once
// What the stages of experiment design share and no user needs: the progress question asked
// of DesignOptions::monitor and the random streams (one per stage, so that changing one
// stage's draws leaves the others' unchanged).

#include <cstdint>

#include "kincal/framework/design/experiment_design.hpp"

namespace kincal::design_detail {

enum Stream : std::uint64_t { kCandidateStream = 21, kWorkspaceStream = 22, kRandomStream = 23 };

// Asks options.monitor whether to go on (always, without one).
inline bool keep_going(const DesignOptions& options, const char* stage, long done, long total,
                       int pass = 0) {
  if (!options.monitor) return true;
  DesignStep step;
  step.stage = stage;
  step.done = done;
  step.total = total;
  step.pass = pass;
  return options.monitor(step);
}

}  // namespace kincal::design_detail
